// SPDX-License-Identifier: MIT
// The web page: files of the web root (--web-root; by default `web` beside the depathd
// executable, found through /proc/self/exe, or ../share/depath/web from it once installed).
// `/` and `/jobs/{id}` answer its index.html (the page routes itself), `/assets/...` and other
// top-level files answer the file with its content type. Paths that would leave the root (.., encoded or not, symlinks out of it) are
// refused with 404; the files themselves need no token (the data they load does).
// Without a web root, `/` and `/jobs/{id}` answer a small plain HTML page (jobs with
// links; a job's id, state and progress) built from the same job manager calls.
#pragma once

#include "http/http_common.hpp"

#include <filesystem>
#include <optional>

namespace depath::service::http {

/// The web root to serve: `configured` if not empty (it must be a directory: else
/// Error(invalid_argument)), else the first directory of `web` beside the executable and
/// `../share/depath/web` from it (the installed layout), else none.
std::optional<std::filesystem::path> find_web_root(const std::string& configured);

/// The file under `root` that `relative` (a URL path without the leading '/', already
/// percent-decoded) names, or nullopt if it escapes the root or is not a regular file.
std::optional<std::filesystem::path> resolve_under(const std::filesystem::path& root, const std::string& relative);

void add_static_files(httplib::Server& server, HttpContext& ctx, std::optional<std::filesystem::path> root);

}  // namespace depath::service::http
