#include "server/server.hpp"

#include <stdexcept>
#include <string>
#include <thread>

#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "server/fail.hpp"
#include "server/listener.hpp"

namespace tp::server {

namespace {

std::string url_host(const net::ip::address& a) {
  if (a.is_unspecified()) return "127.0.0.1";
  return a.is_v6() ? "[" + a.to_string() + "]" : a.to_string();
}

}  // namespace

struct Server::Impl {
  ServerOptions opt;
  net::io_context ioc;
  Hub hub;
  RenderLoop loop;
  ServerContext ctx;
  std::shared_ptr<Listener> listener;
  net::steady_timer stats_timer{ioc};
  net::steady_timer shutdown_timer{ioc};
  net::signal_set signals{ioc, SIGINT, SIGTERM};
  net::ip::address addr;

  Impl(ServerOptions o, std::unique_ptr<FrameSource> src)
      : opt(std::move(o)),
        ioc(std::max(1, opt.io_threads)),
        loop(std::move(src), hub, opt.loop),
        ctx{hub, loop, {}, opt.limits} {
    boost::system::error_code ec;
    addr = net::ip::make_address(opt.bind, ec);
    if (ec)  // asio's own message was "Invalid argument", naming nothing
      throw std::runtime_error("--bind " + opt.bind + ": not an IP address (e.g. 127.0.0.1, ::1)");
    try {
      listener = std::make_shared<Listener>(ioc, net::ip::tcp::endpoint{addr, opt.port}, ctx);
    } catch (
        const boost::system::system_error& e) {  // said "bind: Cannot assign requested address"
      throw std::runtime_error("--bind " + opt.bind + " --port " + std::to_string(opt.port) +
                               ": cannot listen: " + e.code().message());
    }
    ctx.policy.port = listener->port();
    ctx.policy.names = {"127.0.0.1", "localhost", "[::1]"};
    if (!addr.is_unspecified()) ctx.policy.names.push_back(url_host(addr));
    for (const auto& h : opt.allow_hosts) ctx.policy.names.push_back(h);
  }

  void tick_stats() {
    stats_timer.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / opt.stats_hz)));
    stats_timer.async_wait([this](boost::system::error_code ec) {
      if (ec) {
        fail(ec, "stats timer");  // cancelled at shutdown: not reported
        return;
      }
      hub.broadcast_text(std::make_shared<const std::string>(loop.stats_message(hub.clients())),
                         true);
      tick_stats();
    });
  }

  void shutdown() {
    listener->stop();
    stats_timer.cancel();
    hub.close_all();  // each client gets a going-away close frame
    // Sessions end as their close handshakes finish; a client that does not answer is cut off
    // by its watchdog, and in any case everything stops after the grace period.
    wait_for_sessions(std::chrono::steady_clock::now() + opt.shutdown_grace);
  }

  void wait_for_sessions(std::chrono::steady_clock::time_point give_up) {
    shutdown_timer.expires_after(std::chrono::milliseconds(20));
    shutdown_timer.async_wait([this, give_up](boost::system::error_code) {
      if (hub.clients() == 0 || std::chrono::steady_clock::now() >= give_up) {
        ioc.stop();
        return;
      }
      wait_for_sessions(give_up);
    });
  }
};

Server::Server(ServerOptions opt, std::unique_ptr<FrameSource> src)
    : impl_(std::make_unique<Impl>(std::move(opt), std::move(src))) {}

Server::~Server() = default;

std::string Server::url() const {
  return "http://" + url_host(impl_->addr) + ":" + std::to_string(impl_->ctx.policy.port) + "/";
}

int Server::run() {
  Impl& m = *impl_;
  m.signals.async_wait([&m](boost::system::error_code ec, int) {
    if (ec) {
      fail(ec, "signals");
      return;
    }
    m.shutdown();
  });
  m.listener->run();
  m.loop.start();
  m.tick_stats();
  std::vector<std::thread> extra;
  for (int i = 1; i < m.opt.io_threads; ++i) extra.emplace_back([&m] { m.ioc.run(); });
  m.ioc.run();
  m.ioc.stop();
  for (auto& t : extra) t.join();
  m.loop.stop();
  return 0;
}

}  // namespace tp::server
