#include "server/listener.hpp"

#include <boost/asio/strand.hpp>

#include "server/fail.hpp"

namespace tp::server {

Listener::Listener(net::io_context& ioc, net::ip::tcp::endpoint ep, ServerContext& ctx)
    : ioc_(ioc), acceptor_(net::make_strand(ioc)), ctx_(ctx) {
  acceptor_.open(ep.protocol());
  acceptor_.set_option(net::socket_base::reuse_address(true));
  acceptor_.bind(ep);
  acceptor_.listen(net::socket_base::max_listen_connections);
  port_ = acceptor_.local_endpoint().port();
}

void Listener::run() { do_accept(); }

void Listener::stop() {
  net::post(acceptor_.get_executor(), [self = shared_from_this()] {
    beast::error_code ignored;
    self->acceptor_.close(ignored);
  });
}

void Listener::do_accept() {
  acceptor_.async_accept(net::make_strand(ioc_),
                         beast::bind_front_handler(&Listener::on_accept, shared_from_this()));
}

void Listener::on_accept(beast::error_code ec, net::ip::tcp::socket socket) {
  if (ec == net::error::operation_aborted || !acceptor_.is_open()) return;  // stop()
  if (ec)
    fail(ec, "accept");  // e.g. out of file descriptors: keep accepting, as Beast's examples do
  else
    std::make_shared<HttpSession>(std::move(socket), ctx_)->run();
  do_accept();
}

}  // namespace tp::server
