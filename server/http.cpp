#include "server/http.hpp"

#include "server/assets.hpp"

namespace tp::server {
namespace {

Response plain(const Request& req, http::status st, std::string body) {
  Response res{st, req.version()};
  res.set(http::field::server, "tinyphong");
  res.set(http::field::content_type, "text/plain; charset=utf-8");
  res.keep_alive(req.keep_alive());
  const std::size_t length = body.size();
  // A response to HEAD has the headers of the GET response and no body (RFC 9110, 9.3.2): a body
  // would be read as the start of the next response on a kept-alive connection.
  if (req.method() != http::verb::head) res.body() = std::move(body);
  res.prepare_payload();
  if (req.method() == http::verb::head) res.content_length(length);
  return res;
}

}  // namespace

bool HostPolicy::host_ok(std::string_view host) const {
  const std::string suffix = ":" + std::to_string(port);
  for (const auto& n : names)
    if (host == n + suffix) return true;
  return false;
}

bool HostPolicy::origin_ok(std::string_view origin) const {
  if (origin.empty()) return true;  // browsers always send Origin on a WebSocket; tools may not
  constexpr std::string_view scheme = "http://";
  if (origin.substr(0, scheme.size()) != scheme) return false;
  return host_ok(origin.substr(scheme.size()));
}

Response route(const Request& req, const HostPolicy& policy) {
  // RFC 7230, 5.4: a request with more than one Host gets 400 (the first alone was checked).
  if (req.count(http::field::host) > 1)
    return plain(req, http::status::bad_request, "more than one Host header\n");
  if (!policy.host_ok(req[http::field::host]))
    return plain(req, http::status::forbidden, "forbidden host\n");
  if (req.method() != http::verb::get && req.method() != http::verb::head) {
    auto res = plain(req, http::status::method_not_allowed, "GET only\n");
    res.set(http::field::allow, "GET, HEAD");
    return res;
  }
  std::string_view target = req.target();
  if (target.find('?') != std::string_view::npos) target = target.substr(0, target.find('?'));
  if (target == "/") target = "/index.html";
  for (const Asset& a : assets()) {
    if (a.path != target) continue;
    Response res{http::status::ok, req.version()};
    res.set(http::field::server, "tinyphong");
    res.set(http::field::content_type, a.mime);
    res.set(http::field::cache_control, "no-store");
    // The page runs only its own scripts and talks only to this server: 'self' covers the
    // WebSocket of the page's own host and port (CSP Level 3); "ws:" would allow any host.
    res.set("Content-Security-Policy",
            "default-src 'self'; connect-src 'self'; img-src 'self' data:; frame-ancestors 'none'");
    res.set("X-Content-Type-Options", "nosniff");
    res.keep_alive(req.keep_alive());
    if (req.method() == http::verb::get) res.body() = std::string(a.body);
    res.prepare_payload();
    if (req.method() == http::verb::head) res.content_length(a.body.size());
    return res;
  }
  return plain(req, http::status::not_found, "not found\n");
}

namespace {

// The parser's errors that mean the request itself is malformed (RFC 9112: answered with 400),
// as against the connection's end or the size limits.
bool malformed_request(boost::beast::error_code ec) {
  for (const http::error e :
       {http::error::bad_line_ending, http::error::bad_method, http::error::bad_target,
        http::error::bad_version, http::error::bad_field, http::error::bad_value,
        http::error::bad_content_length, http::error::bad_transfer_encoding, http::error::bad_chunk,
        http::error::bad_chunk_extension, http::error::bad_obs_fold})
    if (ec == e) return true;
  return false;
}

}  // namespace

std::optional<Response> refusal_for(boost::beast::error_code ec) {
  http::status st{};
  std::string why;
  if (ec == http::error::body_limit) {
    st = http::status::payload_too_large;
  } else if (ec == http::error::header_limit) {
    st = http::status::request_header_fields_too_large;
  } else if (malformed_request(ec)) {
    st = http::status::bad_request;
    why = ": " + ec.message();  // the parser's words: "bad method", "bad Content-Length", ...
  } else {
    return std::nullopt;
  }
  Response res{st, 11};
  res.set(http::field::server, "tinyphong");
  res.set(http::field::content_type, "text/plain; charset=utf-8");
  res.keep_alive(false);
  res.body() = std::string(obsolete_reason(st)) + why + "\n";
  res.prepare_payload();
  return res;
}

std::string check_upgrade(const Request& req, const HostPolicy& policy, http::status& status) {
  status = http::status::bad_request;
  if (req.count(http::field::host) > 1) return "more than one Host header";
  status = http::status::forbidden;
  if (!policy.host_ok(req[http::field::host])) return "forbidden host";
  // Only the first Origin would have been checked; browsers send one.
  if (req.count(http::field::origin) > 1) return "forbidden origin";
  if (!policy.origin_ok(req[http::field::origin])) return "forbidden origin";
  status = http::status::not_found;
  if (req.target() != "/ws") return "no WebSocket at this path";
  return "";
}

}  // namespace tp::server
