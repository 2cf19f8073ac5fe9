// One HTTP connection (Beast 1.74 advanced_server's http_session, without pipelining: one
// request at a time). Serves the embedded page; hands a WebSocket upgrade to /ws over to a
// WsSession after the Host/Origin checks.
#pragma once
#include <array>
#include <chrono>
#include <memory>
#include <optional>

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include "server/http.hpp"
#include "server/ws_session.hpp"

namespace tp::server {

struct ServerContext {
  Hub& hub;
  RenderLoop& loop;
  HostPolicy policy;
  SessionLimits limits;
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(net::ip::tcp::socket&& socket, ServerContext& ctx);
  void run();

 private:
  void do_read();
  void on_read(beast::error_code ec, std::size_t n);
  void send(Response res);
  void on_write(bool close, beast::error_code ec, std::size_t n);
  void drain(std::size_t budget);

  static constexpr std::size_t kDrainBytes = 1 << 20;
  static constexpr std::chrono::seconds kDrainTime{2};

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  ServerContext& ctx_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<Response> res_;
  bool drain_after_send_ = false;
  std::array<char, 4096> discard_{};
};

}  // namespace tp::server
