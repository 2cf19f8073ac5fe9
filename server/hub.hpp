// The registry of WebSocket sessions and the shared "latest" slots. Producers (render loop,
// reference worker, stats timer) call it from any thread; it only posts to each session's
// strand, so a producer never waits for a client.
#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "server/protocol.hpp"

namespace tp::server {

class WsSession;
using TextPtr = std::shared_ptr<const std::string>;

class Hub {
 public:
  void join(const std::shared_ptr<WsSession>& s);
  void publish_frame(FramePtr f);  // device or reference frame
  // The reference was switched off: a client that joins from now on gets no reference frame, and
  // no session sends one it has not sent yet (it would come after the "off" state, text going
  // first, and show a comparison nobody asked for). Called with the render loop's lock held, so a
  // reference worker that saw it still on cannot publish after this.
  void forget_reference();
  void broadcast_text(TextPtr msg, bool droppable);
  void set_state(TextPtr state);  // the latest "state" message, also sent on join
  void close_all();               // going away (shutdown)
  std::size_t clients();
  FramePtr latest_device();

 private:
  // The sessions still open, taken with m_ held, to be called after it is released.
  std::vector<std::shared_ptr<WsSession>> live_sessions_locked();

  std::mutex m_;
  std::vector<std::weak_ptr<WsSession>> sessions_;
  FramePtr latest_device_, latest_reference_;
  TextPtr state_;
  bool closing_ = false;
};

}  // namespace tp::server
