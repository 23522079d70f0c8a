// SPDX-License-Identifier: MIT
#include "http/static_files.hpp"

#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"
#include "http/job_json.hpp"

#include <fstream>
#include <sstream>
#include <unistd.h>

namespace depath::service::http {

namespace fs = std::filesystem;

namespace {

// Debian's cpp-httplib compresses text/*, application/json and application/javascript
// with brotli at its slowest setting when the browser accepts it (15 s for bunny's
// geometry, 4 s for app.js); the "; charset" forms of the two big ones are left alone.
const char* content_type(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "application/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json" || ext == ".map") return "application/json; charset=utf-8";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  if (ext == ".ico") return "image/x-icon";
  if (ext == ".wasm") return "application/wasm";
  if (ext == ".woff2") return "font/woff2";
  if (ext == ".txt") return "text/plain; charset=utf-8";
  return "application/octet-stream";
}

bool send_file(httplib::Response& res, const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return false;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  res.set_content(bytes.str(), content_type(file));
  return true;
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

// The page when no web root is installed: plain HTML from the same job manager calls.
std::string fallback_page(HttpContext& ctx, const httplib::Request& req, const std::string& job_id) {
  std::string body = "<!doctype html><html><head><meta charset=\"utf-8\"><title>depath";
  if (!job_id.empty()) body.append(" ").append(html_escape(job_id));
  body += "</title></head><body><h1><a href=\"/\">depath</a></h1>\n"
          "<p>The web page is not installed (no --web-root); this is the plain view.</p>\n";
  httplib::Response probe;
  if (!authorized(ctx, req, probe)) {
    return body + "<p>This server requires a token: open the page with ?access_token=TOKEN.</p></body></html>\n";
  }
  try {
    if (!job_id.empty()) {
      const v1::JobInfo info = ctx.service.jobs.get(job_id);
      const auto summary = job_summary(info);
      body += "<h2 id=\"job\">" + html_escape(info.job_id()) + "</h2>\n<p>state: <b>" +
              html_escape(summary["state"].get<std::string>()) + "</b>";
      if (info.has_last_progress()) {
        body += ", generation " + std::to_string(info.last_progress().generation()) + ", best energy " +
                summary["best_energy"].dump();
      }
      if (!info.error_message().empty()) body += ", " + html_escape(info.error_message());
      body += "</p>\n<p>Data: <a href=\"/v1/jobs/" + html_escape(info.job_id()) + "\">JSON</a></p>\n";
    } else {
      body += "<ul>\n";
      const v1::ListJobsResponse list = ctx.service.jobs.list({});
      for (const auto& info : list.jobs()) {
        body += "<li><a href=\"/jobs/" + html_escape(info.job_id()) + "\">" + html_escape(info.job_id()) +
                "</a> " + wire::state_name(info.state()) + "</li>\n";
      }
      body += "</ul>\n";
    }
  } catch (const std::exception& e) {
    body += "<p>" + html_escape(e.what()) + "</p>\n";
  }
  return body + "</body></html>\n";
}

}  // namespace

std::optional<fs::path> find_web_root(const std::string& configured) {
  std::error_code ec;
  if (!configured.empty()) {
    if (!fs::is_directory(configured, ec))
      throw Error(ErrorCode::invalid_argument, "--web-root '" + configured + "' is not a directory");
    return fs::canonical(configured);
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return std::nullopt;
  // The build tree and the image keep it beside the executable; `cmake --install` puts
  // depathd in PREFIX/bin and the page in PREFIX/share/depath/web.
  for (const fs::path& candidate :
       {exe.parent_path() / "web", exe.parent_path().parent_path() / "share/depath/web"}) {
    if (fs::is_directory(candidate, ec)) {
      auto root = fs::canonical(candidate, ec);
      if (!ec) return root;
    }
  }
  return std::nullopt;
}

std::optional<fs::path> resolve_under(const fs::path& root, const std::string& relative) {
  if (relative.find('\0') != std::string::npos || relative.find('\\') != std::string::npos) return std::nullopt;
  const fs::path rel(relative);
  if (rel.is_absolute()) return std::nullopt;
  for (const auto& part : rel) {
    if (part == "..") return std::nullopt;
  }
  std::error_code ec;
  const fs::path file = fs::canonical(root / rel, ec);  // resolves symlinks: they must stay inside too
  if (ec || !fs::is_regular_file(file, ec)) return std::nullopt;
  const auto [r, f] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
  if (r != root.end()) return std::nullopt;
  return file;
}

void add_static_files(httplib::Server& server, HttpContext& ctx, std::optional<fs::path> root) {
  auto page = [&ctx, root](const httplib::Request& req, httplib::Response& res, const std::string& job_id) {
    if (root) {
      if (auto index = resolve_under(*root, "index.html"); index && send_file(res, *index)) return;
    }
    res.set_content(fallback_page(ctx, req, job_id), "text/html; charset=utf-8");
  };
  server.Get("/", [page](const httplib::Request& req, httplib::Response& res) { page(req, res, ""); });
  server.Get(R"(/jobs/([^/]+))",
             [page](const httplib::Request& req, httplib::Response& res) { page(req, res, req.matches[1]); });
  // Files: /assets/... and top-level files (favicon.ico); never /v1, which the API owns.
  server.Get(R"(/((?!v1/)[^?]+))", [root](const httplib::Request& req, httplib::Response& res) {
    std::optional<fs::path> file;
    if (root) file = resolve_under(*root, req.matches[1]);
    if (!file || !send_file(res, *file)) {
      res.status = 404;
      res.set_content("not found\n", "text/plain");
    }
  });
}

}  // namespace depath::service::http
