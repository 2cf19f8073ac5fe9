// The whole server: I/O context, listener, hub, render loop, statistics timer and graceful
// shutdown on SIGINT/SIGTERM (going-away close frames, exit within a bounded time).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "server/frame_source.hpp"
#include "server/render_loop.hpp"
#include "server/ws_session.hpp"

namespace tp::server {

struct ServerOptions {
  std::string bind = "127.0.0.1";
  std::vector<std::string> allow_hosts;  // extra Host names accepted (e.g. a LAN name with --bind)
  unsigned short port = 8080;            // 0: pick a free port
  int io_threads = 1;
  double stats_hz = 4;
  std::chrono::milliseconds shutdown_grace{1500};
  LoopOptions loop;
  SessionLimits limits;
};

class Server {
 public:
  // Binds at once (throws boost::system::system_error if it cannot).
  Server(ServerOptions opt, std::unique_ptr<FrameSource> src);
  ~Server();
  std::string url() const;
  int run();  // until SIGINT/SIGTERM

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tp::server
