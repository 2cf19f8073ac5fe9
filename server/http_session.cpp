#include "server/http_session.hpp"

#include <algorithm>

#include <boost/asio/dispatch.hpp>

#include "server/fail.hpp"

namespace tp::server {

HttpSession::HttpSession(net::ip::tcp::socket&& socket, ServerContext& ctx)
    : stream_(std::move(socket)), ctx_(ctx) {}

void HttpSession::run() {
  net::dispatch(stream_.get_executor(),
                beast::bind_front_handler(&HttpSession::do_read, shared_from_this()));
}

void HttpSession::do_read() {
  parser_.emplace();
  parser_->header_limit(8 * 1024);  // requests are tiny: GETs and the upgrade
  parser_->body_limit(1024);
  stream_.expires_after(std::chrono::seconds(10));
  http::async_read(stream_, buffer_, *parser_,
                   beast::bind_front_handler(&HttpSession::on_read, shared_from_this()));
}

void HttpSession::on_read(beast::error_code ec, std::size_t) {
  if (ec) {  // end of stream, timeout, a malformed or oversized request: answer if due, close
    // A kept-alive connection that times out before its next request starts is an orderly end
    // (a browser keeps one open after loading the page), like end_of_stream.
    const bool idle = ec == beast::error::timeout && !parser_->got_some();
    if (!idle) fail(ec, "http read");
    if (auto refusal = refusal_for(ec)) {  // a malformed or too large request gets its answer
      drain_after_send_ = true;
      send(std::move(*refusal));
      return;
    }
    beast::error_code ignored;
    stream_.socket().shutdown(net::ip::tcp::socket::shutdown_send, ignored);
    return;
  }
  Request req = parser_->release();
  if (websocket::is_upgrade(req)) {
    http::status st{};
    if (auto why = check_upgrade(req, ctx_.policy, st); !why.empty()) {
      Response res{st, req.version()};
      res.set(http::field::content_type, "text/plain; charset=utf-8");
      res.body() = why + "\n";
      res.keep_alive(false);
      res.prepare_payload();
      send(std::move(res));
      return;
    }
    std::make_shared<WsSession>(std::move(stream_), ctx_.hub, ctx_.loop, ctx_.limits)
        ->run(std::move(req));
    return;
  }
  send(route(req, ctx_.policy));
}

void HttpSession::send(Response res) {
  res_ = std::make_shared<Response>(std::move(res));
  const bool close = res_->need_eof();
  http::async_write(stream_, *res_,
                    beast::bind_front_handler(&HttpSession::on_write, shared_from_this(), close));
}

void HttpSession::on_write(bool close, beast::error_code ec, std::size_t) {
  res_.reset();
  if (ec) {
    fail(ec, "http write");
    return;
  }
  if (close) {
    beast::error_code ignored;
    stream_.socket().shutdown(net::ip::tcp::socket::shutdown_send, ignored);
    if (drain_after_send_) {
      stream_.expires_after(kDrainTime);  // one deadline for the whole drain, not one per read
      drain(kDrainBytes);
    }
    return;
  }
  do_read();
}

// Closing a socket with unread bytes sends a reset, which can destroy the answer before the
// client reads it; so after refusing a request (too large or malformed), read what the client sends
// until it closes, for at most kDrainBytes and kDrainTime in all.
void HttpSession::drain(std::size_t budget) {
  if (budget == 0) return;
  stream_.async_read_some(net::buffer(discard_),
                          [self = shared_from_this(), budget](beast::error_code ec, std::size_t n) {
                            if (!ec) self->drain(budget - std::min(budget, n));
                          });
}

}  // namespace tp::server
