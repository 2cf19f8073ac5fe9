// Accepts connections and gives each its own strand (Beast 1.74 advanced_server's listener).
#pragma once
#include <memory>

#include <boost/asio/ip/tcp.hpp>

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

  net::io_context& ioc_;
  net::ip::tcp::acceptor acceptor_;
  ServerContext& ctx_;
  unsigned short port_ = 0;
};

}  // namespace tp::server
