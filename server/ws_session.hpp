// One WebSocket client (structure of Beast 1.74's websocket_server_async / advanced_server:
// the session owns its stream, all its handlers run on the stream's strand, writes go through
// an explicit queue). Backpressure: at most kMaxInFlight unacknowledged frames, one "latest
// frame" slot per kind that a newer frame replaces, a bounded text queue, and a write/ack
// deadline that closes a client that stops reading.
#pragma once
#include <chrono>
#include <deque>
#include <memory>
#include <string>
#include <string_view>

#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include "server/control.hpp"
#include "server/http.hpp"
#include "server/hub.hpp"

namespace tp::server {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;

class RenderLoop;

struct SessionLimits {
  std::size_t max_in_flight = 2;               // unacknowledged frames per client
  std::size_t max_text_queue = 64;             // queued text messages before dropping / closing
  std::chrono::milliseconds deadline{5000};    // write pending or frame unacked this long → close
  std::size_t hard_message_limit = 64 * 1024;  // Beast read_message_max: beyond this, close 1009
};

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(beast::tcp_stream&& stream, Hub& hub, RenderLoop& loop, SessionLimits limits);
  void run(Request req);  // accepts the upgrade carried by req

  // Called from any thread (via the hub); each posts to the strand.
  void offer_frame(FramePtr f);
  void drop_reference();  // the reference was switched off: a reference frame not yet sent goes
  void offer_text(TextPtr msg, bool droppable);
  void close_going_away();

 private:
  void on_accept(beast::error_code ec);
  void do_read();
  void on_read(beast::error_code ec, std::size_t n);
  // Reads the next message unless a read is pending or the client has half a text queue waiting
  // for it: queued messages of any kind, and replies still with the render loop. A client that
  // sends faster than its replies can be written waits for them instead of overflowing its queue.
  void resume_reading();
  void handle_text(const std::string& text);
  void handle_ack(const Command& c);
  // {"type":"ok"|"error","request":request[,"error":…]}; request is "" when the message names
  // no type the server knows (or is not JSON, or is binary).
  void reply(std::string_view request, const Result& outcome);
  void queue_text(TextPtr msg, bool droppable);
  void pump();
  void on_write(beast::error_code ec, std::size_t n);
  void arm_watchdog();
  void on_watchdog(beast::error_code ec);
  void abort();

  struct Pending {
    TextPtr text;
    bool droppable;
  };
  struct InFlight {
    FrameKind kind;
    std::uint32_t id;
    std::chrono::steady_clock::time_point sent;
  };

  websocket::stream<beast::tcp_stream> ws_;
  Hub& hub_;
  RenderLoop& loop_;
  SessionLimits limits_;
  beast::flat_buffer buffer_;
  net::steady_timer watchdog_;
  std::deque<Pending> text_q_;
  FramePtr latest_[2];  // by FrameKind: the newest frame not yet sent
  std::deque<InFlight> in_flight_;
  FramePtr writing_frame_;  // keeps the buffer alive during async_write
  TextPtr writing_text_;
  bool writing_ = false, open_ = false, closing_ = false, reading_ = false;
  std::size_t awaiting_ = 0;  // control messages with the render loop, each owed a reply
  std::chrono::steady_clock::time_point write_started_, closing_since_;
};

}  // namespace tp::server
