// SPDX-License-Identifier: MIT
#include "log.hpp"

#include "depath/util/error.hpp"

#include <spdlog/sinks/stdout_sinks.h>

#include <chrono>
#include <ctime>

namespace depath::service {

Log::Log(const std::string& format, const std::string& level) {
  if (format != "text" && format != "json") {
    throw Error(ErrorCode::invalid_argument, "--log-format must be text or json (got '" + format + "')");
  }
  json_ = format == "json";
  logger_ = std::make_shared<spdlog::logger>("depathd", std::make_shared<spdlog::sinks::stderr_sink_mt>());
  // JSON lines carry their own time and level; text lines get spdlog's.
  logger_->set_pattern(json_ ? "%v" : "%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
  logger_->set_level(spdlog::level::from_str(level));
  logger_->flush_on(spdlog::level::info);
}

void Log::write(spdlog::level::level_enum level, std::string_view event, const nlohmann::json& fields) {
  if (!logger_->should_log(level)) return;
  if (json_) {
    const auto now = std::chrono::system_clock::now();
    const double t = std::chrono::duration<double>(now.time_since_epoch()).count();
    nlohmann::json line = {{"time", t}, {"level", spdlog::level::to_string_view(level).data()}, {"event", event}};
    for (auto it = fields.begin(); it != fields.end(); ++it) line[it.key()] = it.value();
    logger_->log(level, "{}", line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  } else {
    std::string text(event);
    for (auto it = fields.begin(); it != fields.end(); ++it) {
      text += ' ';
      text += it.key();
      text += '=';
      text += it.value().is_string() ? it.value().get<std::string>() : it.value().dump();
    }
    logger_->log(level, "{}", text);
  }
}

}  // namespace depath::service
