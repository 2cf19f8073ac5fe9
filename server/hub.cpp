#include "server/hub.hpp"

#include "server/ws_session.hpp"

namespace tp::server {

void Hub::join(const std::shared_ptr<WsSession>& s) {
  FramePtr dev, ref;
  TextPtr state;
  {
    std::lock_guard lk(m_);
    if (closing_) {
      s->close_going_away();
      return;
    }
    std::erase_if(sessions_, [](const std::weak_ptr<WsSession>& w) { return w.expired(); });
    sessions_.push_back(s);
    dev = latest_device_;
    ref = latest_reference_;
    state = state_;
  }
  if (state) s->offer_text(state, false);
  if (dev) s->offer_frame(dev);
  if (ref && dev && ref->id == dev->id) s->offer_frame(ref);
}

std::vector<std::shared_ptr<WsSession>> Hub::live_sessions_locked() {
  std::vector<std::shared_ptr<WsSession>> live;
  for (auto& w : sessions_)
    if (auto s = w.lock()) live.push_back(std::move(s));
  return live;
}

void Hub::publish_frame(FramePtr f) {
  std::vector<std::shared_ptr<WsSession>> targets;
  {
    std::lock_guard lk(m_);
    if (closing_) return;  // shutting down: clients only get their close frame now
    (f->kind == FrameKind::device ? latest_device_ : latest_reference_) = f;
    targets = live_sessions_locked();
  }
  for (auto& s : targets) s->offer_frame(f);
}

void Hub::forget_reference() {
  std::vector<std::shared_ptr<WsSession>> targets;
  {
    std::lock_guard lk(m_);
    latest_reference_.reset();
    targets = live_sessions_locked();
  }
  for (auto& s : targets) s->drop_reference();
}

void Hub::broadcast_text(TextPtr msg, bool droppable) {
  std::vector<std::shared_ptr<WsSession>> targets;
  {
    std::lock_guard lk(m_);
    if (closing_) return;
    targets = live_sessions_locked();
  }
  for (auto& s : targets) s->offer_text(msg, droppable);
}

void Hub::set_state(TextPtr state) {
  {
    std::lock_guard lk(m_);
    state_ = state;
  }
  broadcast_text(std::move(state), false);
}

void Hub::close_all() {
  std::vector<std::shared_ptr<WsSession>> targets;
  {
    std::lock_guard lk(m_);
    closing_ = true;
    targets = live_sessions_locked();
  }
  for (auto& s : targets) s->close_going_away();
}

std::size_t Hub::clients() {
  std::lock_guard lk(m_);
  std::erase_if(sessions_, [](const std::weak_ptr<WsSession>& w) { return w.expired(); });
  return sessions_.size();
}

FramePtr Hub::latest_device() {
  std::lock_guard lk(m_);
  return latest_device_;
}

}  // namespace tp::server
