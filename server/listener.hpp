// Accepts connections and gives each its own strand (Beast 1.74 advanced_server's listener).
// When the process runs out of descriptors or memory, accepting fails at once for as long as the
// clients hold theirs: the listener then waits kStarvedRetry between attempts and reports the
// episode once, instead of spinning and logging every attempt.
#pragma once
#include <chrono>
#include <memory>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>

#include "server/http_session.hpp"

namespace tp::server {

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  // Throws boost::system::system_error if the endpoint cannot be bound.
  Listener(net::io_context& ioc, net::ip::tcp::endpoint ep, ServerContext& ctx);
  unsigned short port() const { return port_; }
  void run();
  void stop();

 private:
  void do_accept();
  void on_accept(beast::error_code ec, net::ip::tcp::socket socket);
  void retry_later();

  static constexpr std::chrono::milliseconds kStarvedRetry{100};

  net::io_context& ioc_;
  net::ip::tcp::acceptor acceptor_;
  net::steady_timer retry_;
  bool starved_ = false;  // accepting failed for want of a resource, and has not succeeded since
  ServerContext& ctx_;
  unsigned short port_ = 0;
};

}  // namespace tp::server
