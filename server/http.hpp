// HTTP routing for the page and the WebSocket upgrade checks. Pure functions over Beast
// messages so the tests can call them without a socket.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <boost/beast/http.hpp>

namespace tp::server {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

// Which Host/Origin values the server accepts: its own name(s) with the port it listens on.
// Anything else is a cross-site page or a DNS-rebinding attempt.
struct HostPolicy {
  std::vector<std::string> names;  // "127.0.0.1", "localhost", "[::1]", the bind address
  unsigned short port = 0;
  bool host_ok(std::string_view host) const;      // "name:port"
  bool origin_ok(std::string_view origin) const;  // "http://name:port"; absent = non-browser client
};

// The page and its assets from the embedded allow-list; 404 for anything else (including
// traversal attempts: the target is compared as a whole, never joined to a directory);
// 403 for a foreign Host; 405 for methods other than GET/HEAD.
Response route(const Request& req, const HostPolicy& policy);

// The answer to a request the parser refused: 413 for a body over the limit, 431 for headers
// over it, 400 for a malformed request (with the parser's reason), each closing the connection
// (the rest of the request is read and dropped, HttpSession::drain). None for any other read
// error (end of stream, a request cut short, timeout): the connection closes.
std::optional<Response> refusal_for(boost::beast::error_code ec);

// "" if a WebSocket upgrade to /ws may proceed, else the reason (answered with 403/404).
std::string check_upgrade(const Request& req, const HostPolicy& policy, http::status& status);

}  // namespace tp::server
