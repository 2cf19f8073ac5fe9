#include "server/ws_session.hpp"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "server/fail.hpp"
#include "server/render_loop.hpp"

namespace tp::server {

WsSession::WsSession(beast::tcp_stream&& stream, Hub& hub, RenderLoop& loop, SessionLimits limits)
    : ws_(std::move(stream)),
      hub_(hub),
      loop_(loop),
      limits_(limits),
      watchdog_(ws_.get_executor()) {}

void WsSession::run(Request req) {
  // Beast's own timeouts cover the handshake and dead peers (pings); our watchdog covers a peer
  // that is alive but does not read (the TCP window stays full, or acks stop).
  websocket::stream_base::timeout t{};
  t.handshake_timeout = std::chrono::seconds(5);
  t.idle_timeout = std::chrono::seconds(60);
  t.keep_alive_pings = true;
  ws_.set_option(t);
  websocket::permessage_deflate pmd;  // frames are raw pixels: no compression, no zip bombs
  pmd.server_enable = false;
  pmd.client_enable = false;
  ws_.set_option(pmd);
  ws_.read_message_max(limits_.hard_message_limit);
  ws_.auto_fragment(false);
  ws_.set_option(websocket::stream_base::decorator(
      [](websocket::response_type& res) { res.set(http::field::server, "tinyphong"); }));
  beast::get_lowest_layer(ws_).expires_never();
  ws_.async_accept(req, beast::bind_front_handler(&WsSession::on_accept, shared_from_this()));
}

void WsSession::on_accept(beast::error_code ec) {
  if (ec) {
    fail(ec, "websocket accept");
    return;
  }
  open_ = true;
  arm_watchdog();
  hub_.join(shared_from_this());
  do_read();
}

void WsSession::do_read() {
  reading_ = true;
  ws_.async_read(buffer_, beast::bind_front_handler(&WsSession::on_read, shared_from_this()));
}

void WsSession::resume_reading() {
  if (reading_ || !open_ || closing_) return;
  // Queued text of any kind counts (a reply, a state, statistics): each leaves only by a write,
  // and on_write resumes. At least one, so that a queue of one still reads.
  if (text_q_.size() + awaiting_ >= std::max<std::size_t>(1, limits_.max_text_queue / 2)) return;
  do_read();
}

void WsSession::on_read(beast::error_code ec, std::size_t) {
  reading_ = false;
  if (ec) {  // closed by the peer, too big (Beast already sent close 1009), or aborted
    if (open_) fail(ec, "websocket read");  // not after our own abort()
    abort();
    return;
  }
  if (ws_.got_text()) {
    handle_text(beast::buffers_to_string(buffer_.data()));
  } else {
    reply("", Result::failure("binary messages are not accepted"));
  }
  buffer_.consume(buffer_.size());
  resume_reading();
}

void WsSession::handle_text(const std::string& text) {
  ParseResult p = parse_control(text);
  if (!p.command) {
    reply(p.type == ControlType::unknown ? "" : to_string(p.type), Result::failure(p.error));
    return;
  }
  const Command& c = *p.command;
  // ack and get_state are answered here, on the session's strand; the rest go to the render loop.
  if (c.type == ControlType::ack) {
    handle_ack(c);
    return;
  }
  if (c.type == ControlType::get_state) {
    queue_text(loop_.state_message(), false);
    return;
  }
  std::weak_ptr<WsSession> weak = weak_from_this();
  const ControlType type = c.type;
  auto done = [weak, type](const Result& outcome) {
    if (auto self = weak.lock())
      net::post(self->ws_.get_executor(), [self, type, outcome] {
        --self->awaiting_;
        self->reply(to_string(type), outcome);
        self->resume_reading();
      });
  };
  ++awaiting_;
  if (Result busy = loop_.submit(c, std::move(done)); !busy.ok()) {
    --awaiting_;
    reply(to_string(type), busy);
  }
}

void WsSession::handle_ack(const Command& c) {
  const auto kind = static_cast<FrameKind>(c.ack_kind);
  for (auto it = in_flight_.begin(); it != in_flight_.end(); ++it) {
    if (it->kind == kind && it->id == c.ack_id) {
      in_flight_.erase(it);
      pump();
      return;
    }
  }
  reply(to_string(ControlType::ack),
        Result::failure("no frame " + std::to_string(c.ack_id) + " in flight"));
}

void WsSession::reply(std::string_view request, const Result& outcome) {
  nlohmann::json j = {{"type", outcome.ok() ? "ok" : "error"}, {"request", request}};
  if (!outcome.ok()) j["error"] = outcome.message();
  queue_text(std::make_shared<const std::string>(json_text(j)), false);
}

void WsSession::offer_frame(FramePtr f) {
  net::post(ws_.get_executor(), [self = shared_from_this(), f = std::move(f)]() mutable {
    if (!self->open_ || self->closing_) return;
    self->latest_[static_cast<int>(f->kind)] = std::move(f);  // a newer frame replaces the slot
    self->pump();
  });
}

void WsSession::drop_reference() {
  net::post(ws_.get_executor(), [self = shared_from_this()] {
    self->latest_[static_cast<int>(FrameKind::reference)].reset();
  });
}

void WsSession::offer_text(TextPtr msg, bool droppable) {
  net::post(ws_.get_executor(),
            [self = shared_from_this(), msg = std::move(msg), droppable]() mutable {
              self->queue_text(std::move(msg), droppable);
            });
}

void WsSession::queue_text(TextPtr msg, bool droppable) {
  if (!open_ || closing_) return;
  if (text_q_.size() >= limits_.max_text_queue) {
    auto it =
        std::find_if(text_q_.begin(), text_q_.end(), [](const Pending& p) { return p.droppable; });
    if (it != text_q_.end()) {
      text_q_.erase(it);  // stale statistics go first
    } else if (droppable) {
      return;
    } else {
      abort();  // the client does not read its replies: it cannot be served within bounds
      return;
    }
  }
  text_q_.push_back({std::move(msg), droppable});
  pump();
}

void WsSession::pump() {
  if (writing_ || !open_ || closing_) return;
  if (!text_q_.empty()) {
    writing_text_ = std::move(text_q_.front().text);
    text_q_.pop_front();
    ws_.text(true);
    writing_ = true;
    write_started_ = std::chrono::steady_clock::now();
    ws_.async_write(net::buffer(*writing_text_),
                    beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
    return;
  }
  if (in_flight_.size() >= limits_.max_in_flight) return;  // wait for the client's acks
  for (auto& slot : latest_) {
    if (!slot) continue;
    writing_frame_ = std::move(slot);
    slot.reset();
    const auto now = std::chrono::steady_clock::now();
    in_flight_.push_back({writing_frame_->kind, writing_frame_->id, now});
    ws_.binary(true);
    writing_ = true;
    write_started_ = now;
    ws_.async_write(net::buffer(writing_frame_->bytes),
                    beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
    return;
  }
}

void WsSession::on_write(beast::error_code ec, std::size_t) {
  writing_ = false;
  writing_frame_.reset();
  writing_text_.reset();
  if (ec) {
    if (open_) fail(ec, "websocket write");  // not after our own abort()
    abort();
    return;
  }
  pump();
  resume_reading();
}

void WsSession::arm_watchdog() {
  watchdog_.expires_after(std::chrono::milliseconds(250));
  watchdog_.async_wait(beast::bind_front_handler(&WsSession::on_watchdog, shared_from_this()));
}

void WsSession::on_watchdog(beast::error_code ec) {
  if (ec) {
    fail(ec, "websocket watchdog");  // cancelled by abort(): operation_aborted, not reported
    return;
  }
  if (!open_) return;
  const auto now = std::chrono::steady_clock::now();
  const bool write_stuck = writing_ && now - write_started_ > limits_.deadline;
  const bool acks_stopped = !in_flight_.empty() && now - in_flight_.front().sent > limits_.deadline;
  const bool close_stuck = closing_ && now - closing_since_ > std::chrono::seconds(1);
  if (write_stuck || acks_stopped || close_stuck) {
    abort();  // application-level write deadline: the client stopped reading
    return;
  }
  arm_watchdog();
}

void WsSession::close_going_away() {
  net::post(ws_.get_executor(), [self = shared_from_this()] {
    if (!self->open_ || self->closing_) return;
    self->closing_ = true;
    self->closing_since_ = std::chrono::steady_clock::now();  // the close must finish in time too
    self->ws_.async_close(websocket::close_code::going_away, [self](beast::error_code ec) {
      fail(ec, "websocket close");
      self->abort();
    });
  });
}

void WsSession::abort() {
  if (!open_) return;
  open_ = false;
  closing_ = false;
  text_q_.clear();
  latest_[0].reset();
  latest_[1].reset();
  watchdog_.cancel();
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().shutdown(net::ip::tcp::socket::shutdown_both, ignored);
  beast::get_lowest_layer(ws_).socket().close(ignored);
}

}  // namespace tp::server
