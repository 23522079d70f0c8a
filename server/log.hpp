// SPDX-License-Identifier: MIT
// Structured logs of the server: one line per event, as text or JSON (--log-format).
#pragma once

#include <nlohmann/json.hpp>
#include <spdlog/logger.h>

#include <memory>
#include <string>
#include <string_view>

namespace depath::service {

class Log {
 public:
  /// format: "text" or "json"; level: an spdlog level name ("info", "debug", "off", ...).
  Log(const std::string& format, const std::string& level);

  void info(std::string_view event, const nlohmann::json& fields = nlohmann::json::object()) {
    write(spdlog::level::info, event, fields);
  }
  void warn(std::string_view event, const nlohmann::json& fields = nlohmann::json::object()) {
    write(spdlog::level::warn, event, fields);
  }
  void error(std::string_view event, const nlohmann::json& fields = nlohmann::json::object()) {
    write(spdlog::level::err, event, fields);
  }
  void debug(std::string_view event, const nlohmann::json& fields = nlohmann::json::object()) {
    write(spdlog::level::debug, event, fields);
  }

 private:
  void write(spdlog::level::level_enum level, std::string_view event, const nlohmann::json& fields);
  std::shared_ptr<spdlog::logger> logger_;
  bool json_ = false;
};

}  // namespace depath::service
