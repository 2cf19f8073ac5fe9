#include "server/listener.hpp"

#include <boost/asio/strand.hpp>

#include "server/fail.hpp"

namespace tp::server {

Listener::Listener(net::io_context& ioc, net::ip::tcp::endpoint ep, ServerContext& ctx)
    : ioc_(ioc), acceptor_(net::make_strand(ioc)), retry_(acceptor_.get_executor()), ctx_(ctx) {
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
    self->retry_.cancel();
  });
}

void Listener::do_accept() {
  acceptor_.async_accept(net::make_strand(ioc_),
                         beast::bind_front_handler(&Listener::on_accept, shared_from_this()));
}

namespace {

bool out_of_resources(beast::error_code ec) {
  return ec == net::error::no_descriptors ||  // EMFILE
         ec == boost::system::errc::too_many_files_open_in_system ||
         ec == net::error::no_buffer_space || ec == net::error::no_memory;
}

}  // namespace

void Listener::on_accept(beast::error_code ec, net::ip::tcp::socket socket) {
  if (ec == net::error::operation_aborted || !acceptor_.is_open()) return;  // stop()
  if (ec && out_of_resources(ec)) {
    if (!starved_) fail(ec, "accept (waiting for connections to close)");
    starved_ = true;
    retry_later();
    return;
  }
  if (ec) {
    fail(ec, "accept");  // e.g. a connection reset before it was accepted: keep accepting
  } else {
    starved_ = false;
    std::make_shared<HttpSession>(std::move(socket), ctx_)->run();
  }
  do_accept();
}

void Listener::retry_later() {
  retry_.expires_after(kStarvedRetry);
  retry_.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (!ec && self->acceptor_.is_open()) self->do_accept();
  });
}

}  // namespace tp::server
