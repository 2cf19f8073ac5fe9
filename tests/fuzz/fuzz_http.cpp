// Fuzz target: HTTP routing and the Host/Origin policy (server/http.cpp) on arbitrary bytes,
// parsed as a request by Beast with the session's limits (server/http_session.cpp). Properties,
// besides no crash, no hang, no undefined behaviour and no exception:
//  - route() answers 200, 403, 404 or 405 only; 200 only for GET/HEAD with an allowed Host and
//    a target that is one of the embedded assets (query stripped, "/" = "/index.html"); 403
//    whenever the Host is not allowed;
//  - check_upgrade() lets through only /ws with an allowed Host and Origin;
//  - host_ok and origin_ok on the raw input agree with their definition (name:port, http://).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <boost/asio/buffer.hpp>

#include "server/assets.hpp"
#include "server/http.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

namespace http = tp::server::http;

const tp::server::HostPolicy& policy() {
  static const tp::server::HostPolicy p{{"127.0.0.1", "localhost", "[::1]"}, 8080};
  return p;
}

bool is_asset(std::string_view target) {
  if (const auto q = target.find('?'); q != std::string_view::npos) target = target.substr(0, q);
  if (target == "/") target = "/index.html";
  for (const auto& a : tp::server::assets())
    if (a.path == target) return true;
  return false;
}

// The policy's definition, written out again: an exact "name:port".
bool host_allowed(std::string_view host) {
  for (const char* name : {"127.0.0.1", "localhost", "[::1]"})
    if (host == std::string(name) + ":8080") return true;
  return false;
}

void check_policy(std::string_view s) {
  TP_FUZZ_CHECK(policy().host_ok(s) == host_allowed(s), "host_ok is an exact name:port match");
  const bool origin = s.empty() || (s.starts_with("http://") && host_allowed(s.substr(7)));
  TP_FUZZ_CHECK(policy().origin_ok(s) == origin, "origin_ok is empty or http:// + a host");
}

void check_route(const tp::server::Request& req) {
  const tp::server::Response res = tp::server::route(req, policy());
  const auto status = res.result();
  const bool one_host = req.count(http::field::host) <= 1;
  const bool host = one_host && host_allowed(req[http::field::host]);
  const bool get = req.method() == http::verb::get || req.method() == http::verb::head;
  TP_FUZZ_CHECK(status == http::status::ok || status == http::status::bad_request ||
                    status == http::status::forbidden || status == http::status::not_found ||
                    status == http::status::method_not_allowed,
                "route answers 200, 400, 403, 404 or 405");
  TP_FUZZ_CHECK((status == http::status::bad_request) == !one_host,
                "400 exactly for more than one Host header (RFC 7230, 5.4)");
  if (one_host && !host)
    TP_FUZZ_CHECK(status == http::status::forbidden, "a foreign Host gets 403");
  if (status == http::status::ok)
    TP_FUZZ_CHECK(host && get && is_asset(req.target()), "200 only for an asset, by GET/HEAD");

  http::status upgrade_status{};
  const std::string why = tp::server::check_upgrade(req, policy(), upgrade_status);
  if (why.empty())
    TP_FUZZ_CHECK(host && req.count(http::field::origin) <= 1 &&
                      policy().origin_ok(req[http::field::origin]) && req.target() == "/ws",
                  "an upgrade only to /ws from one allowed Host and at most one allowed Origin");
  else
    TP_FUZZ_CHECK(upgrade_status == http::status::bad_request ||
                      upgrade_status == http::status::forbidden ||
                      upgrade_status == http::status::not_found,
                  "a refused upgrade gets 400, 403 or 404");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  check_policy(bytes);
  http::request_parser<http::string_body> parser;
  parser.header_limit(8 * 1024);  // as server/http_session.cpp
  parser.body_limit(1024);
  parser.eager(true);
  boost::system::error_code ec;
  std::size_t used = 0;
  while (used < size && !parser.is_done()) {
    const std::size_t n = parser.put(boost::asio::buffer(data + used, size - used), ec);
    used += n;
    if (ec || n == 0) break;
  }
  if ((ec == http::error::need_more || (!ec && !parser.is_done())) && parser.got_some()) {
    ec = {};
    parser.put_eof(ec);  // the connection ends here (Beast asserts that a message started)
  }
  if (ec || !parser.is_done()) return 0;
  check_route(parser.release());
  return 0;
}
