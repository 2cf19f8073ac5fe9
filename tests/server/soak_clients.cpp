#include "soak_clients.hpp"

#include <optional>

#include "server/protocol.hpp"

namespace tpt::soak {

using nlohmann::json;

void Tally::problem(const std::string& what) {
  std::lock_guard lk(m_);
  problems_.push_back(what);
}

std::vector<std::string> Tally::problems() const {
  std::lock_guard lk(m_);
  return problems_;
}

namespace {

std::chrono::milliseconds left_until(Clock::time_point end) {
  return std::max(1ms, std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()));
}

std::chrono::milliseconds random_ms(Rng& rng, int lo, int hi) {
  return std::chrono::milliseconds(uniform_int(rng, lo, hi));
}

// The frame's header, or nothing if the message is not a valid frame.
std::optional<tp::server::EncodedFrame> frame_header(const std::string& data) {
  tp::server::EncodedFrame h;
  if (!tp::server::decode_header({reinterpret_cast<const std::uint8_t*>(data.data()), data.size()},
                                 h))
    return std::nullopt;
  return h;
}

void note_max(std::atomic<long long>& worst, long long value) {
  long long seen = worst.load();
  while (value > seen && !worst.compare_exchange_weak(seen, value)) {
  }
}

// Reads (acking every frame, like the page) until `end` or an error; the worst gaps between
// device frames go into the tally. False if the connection ended.
bool read_and_ack(WsClient& c, Clock::time_point end, Tally& tally, bool record_gaps) {
  std::optional<Clock::time_point> last;
  while (Clock::now() < end) {
    Message m = c.read(left_until(end));
    if (m.ec == net::error::timed_out) break;
    if (!m.ok) return false;
    if (!m.binary) continue;
    const auto header = frame_header(m.data);
    if (!header) {
      tally.problem("a binary message that is not a valid frame");
      continue;
    }
    c.ack(m.data);
    if (header->kind != tp::server::FrameKind::device || !record_gaps) continue;
    const auto now = Clock::now();
    if (last) {
      const auto gap = std::chrono::duration_cast<std::chrono::microseconds>(now - *last).count();
      note_max(tally.reader_max_gap_us, gap);
      note_max(tally.reader_max_overhead_us,
               gap - static_cast<long long>(header->render_ms * 1000));
    }
    last = now;
    ++tally.reader_frames;
  }
  return true;
}

struct Replies {
  long ok = 0, errors = 0;
  std::vector<std::string> error_texts;
  bool connection_ended = false;
};

// Reads until `expected` ok/error replies arrived (acking frames), at most for timeout.
Replies await_replies(WsClient& c, long expected, std::chrono::milliseconds timeout) {
  Replies r;
  const auto end = Clock::now() + timeout;
  while (r.ok + r.errors < expected && Clock::now() < end) {
    Message m = c.read(left_until(end));
    if (m.ec == net::error::timed_out) break;
    if (!m.ok) {
      r.connection_ended = true;
      break;
    }
    if (m.binary) {
      c.ack(m.data);
      continue;
    }
    const json j = json::parse(m.data, nullptr, false);
    const std::string type = j.is_object() ? j.value("type", "") : "";
    if (type == "ok") ++r.ok;
    if (type == "error") {
      ++r.errors;
      r.error_texts.push_back(j.value("error", ""));
    }
  }
  return r;
}

// Reads until the connection ends (true) or timeout passes (false), never acking.
bool drained_to_end(WsClient& c, std::chrono::milliseconds timeout) {
  const auto end = Clock::now() + timeout;
  while (Clock::now() < end)
    if (!c.read(left_until(end)).ok) return Clock::now() < end;
  return false;
}

// A bounded HTTP exchange: the status, or 0 if the request failed or took longer than timeout.
int http_status(unsigned short port, const std::string& target, const std::string& host,
                std::chrono::milliseconds timeout = 10s) {
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  stream.expires_after(timeout);
  http::request<http::empty_body> req{http::verb::get, target, 11};
  req.set(http::field::host, host);
  beast::flat_buffer buf;
  http::response<http::string_body> res;
  int status = 0;
  stream.async_connect({net::ip::make_address("127.0.0.1"), port}, [&](beast::error_code ec) {
    if (ec) return;
    http::async_write(stream, req, [&](beast::error_code wec, std::size_t) {
      if (wec) return;
      http::async_read(stream, buf, res, [&](beast::error_code rec, std::size_t) {
        if (!rec) status = res.result_int();
      });
    });
  });
  ioc.run();  // bounded by the stream's expiry
  return status;
}

std::string local_host(unsigned short port) { return "127.0.0.1:" + std::to_string(port); }

// --- churn: one random connection, then gone --------------------------------------------------

void churn_reader(WorkerContext& ctx, Rng& rng) {
  WsClient c(ctx.port);
  ++ctx.tally->ws_connections;
  if (!read_and_ack(c, Clock::now() + random_ms(rng, 200, 3000), *ctx.tally, true))
    ctx.tally->problem("a reading client was disconnected by the server");
  if (chance(rng, 0.5) && !c.close()) ctx.tally->problem("no answer to a client's close");
}  // otherwise the socket just goes away (no close frame)

void churn_never_acks(WorkerContext& ctx, Rng& rng) {
  WsClient c(ctx.port);
  ++ctx.tally->ws_connections;
  int frames = 0;
  const auto end = Clock::now() + random_ms(rng, 300, 2000);  // within the 5 s deadline
  while (Clock::now() < end) {
    Message m = c.read(left_until(end));
    if (!m.ok) break;
    frames += m.binary ? 1 : 0;
  }
  if (frames > 2) ctx.tally->problem("more than 2 unacknowledged frames in flight");
}

void churn_send_and_vanish(WorkerContext& ctx, Rng& rng) {
  WsClient c(ctx.port);
  ++ctx.tally->ws_connections;
  // Gone before the reply: the render loop answers a session that no longer exists.
  const ControlMessage msg =
      chance(rng, 0.5) ? random_valid_message(rng, *ctx.catalog) : random_invalid_message(rng);
  c.send(msg.text);
}

void churn_handshake_only(WorkerContext& ctx, Rng& rng) {
  WsClient c(ctx.port);
  ++ctx.tally->ws_connections;
  if (chance(rng, 0.5) && !c.close()) ctx.tally->problem("no answer to a client's close");
}

void churn_foreign_origin(WorkerContext& ctx, Rng&) {
  try {
    WsClient c(ctx.port, "http://evil.example");
    ctx.tally->problem("a foreign Origin was accepted");
  } catch (const boost::system::system_error& e) {
    if (e.code() != websocket::error::upgrade_declined)
      ctx.tally->problem(std::string("foreign Origin: ") + e.what());
  }
  ++ctx.tally->ws_connections;
}

void churn_http(WorkerContext& ctx, Rng& rng) {
  struct Case {
    const char* target;
    bool foreign_host;
    int status;
  };
  static const std::vector<Case> cases = {
      {"/", false, 200},     {"/app.js", false, 200},        {"/style.css", false, 200},
      {"/nope", false, 404}, {"/../etc/passwd", false, 404}, {"/", true, 403}};
  const Case& c = cases[static_cast<std::size_t>(uniform_int(rng, 0, int(cases.size()) - 1))];
  const std::string host =
      c.foreign_host ? "rebind.example:" + std::to_string(ctx.port) : local_host(ctx.port);
  const int got = http_status(ctx.port, c.target, host);
  ++ctx.tally->http_requests;
  if (got != c.status)
    ctx.tally->problem(std::string("GET ") + c.target + ": " + std::to_string(got) + ", expected " +
                       std::to_string(c.status));
}

void churn_raw_tcp(WorkerContext& ctx, Rng& rng) {
  net::io_context ioc;
  tcp::socket s(ioc);
  s.connect({net::ip::make_address("127.0.0.1"), ctx.port});
  ++ctx.tally->raw_connections;
  static const std::vector<std::string> openings = {
      "", "GET / HTTP/1.1\r\nHo", "\x16\x03\x01\x02\x00\x01", "GET /ws HTTP/1.1\r\nUpgrade: "};
  const std::string& bytes =
      openings[static_cast<std::size_t>(uniform_int(rng, 0, int(openings.size()) - 1))];
  beast::error_code ignored;
  if (!bytes.empty()) net::write(s, net::buffer(bytes), ignored);
  s.close(ignored);  // half a request, then gone
}

}  // namespace

void run_churner(WorkerContext ctx) {
  Rng rng(ctx.seed);
  using Action = void (*)(WorkerContext&, Rng&);
  // Weights: mostly page-like readers, then every other way a connection can start and end.
  static const std::vector<std::pair<int, Action>> actions = {
      {35, churn_reader},         {10, churn_never_acks},    {10, churn_send_and_vanish},
      {10, churn_handshake_only}, {5, churn_foreign_origin}, {20, churn_http},
      {10, churn_raw_tcp}};
  while (Clock::now() < ctx.until) {
    int roll = uniform_int(rng, 1, 100);
    for (const auto& [weight, action] : actions) {
      if ((roll -= weight) > 0) continue;
      try {
        action(ctx, rng);
      } catch (const std::exception& e) {
        ctx.tally->problem(std::string("churn: ") + e.what());
      }
      break;
    }
    std::this_thread::sleep_for(random_ms(rng, 0, 100));
  }
}

namespace {

// A message over Beast's 64 KiB limit: the server closes the connection with 1009.
bool closed_as_too_big(WsClient& c) {
  try {
    c.send(std::string(100 * 1024, ' '));
  } catch (const boost::system::system_error& e) {
    // Closed while the message was still being written: the same refusal, seen from here.
    return e.code() != net::error::timed_out;
  }
  // A close frame with 1009, or the connection's end if the server's teardown won the race.
  return drained_to_end(c, 10s);
}

// One burst: n messages without reading, then every reply.
void storm_burst(WorkerContext& ctx, Rng& rng, WsClient& c) {
  const int n = uniform_int(rng, 1, 32);
  long valid = 0;
  for (int i = 0; i < n; ++i) {
    const ControlMessage msg =
        chance(rng, 0.55) ? random_valid_message(rng, *ctx.catalog) : random_invalid_message(rng);
    c.send(msg.text);
    valid += msg.valid ? 1 : 0;
  }
  long sent = n;
  if (chance(rng, 0.05)) {
    c.send_binary("\x01\x02\x03");  // "binary messages are not accepted"
    ++sent;
  }
  ctx.tally->valid_sent += valid;
  ctx.tally->invalid_sent += sent - valid;
  // Generous: a burst waits for the render loop, which applies commands between frames.
  const Replies r = await_replies(c, sent, 30s);
  ctx.tally->ok_replies += r.ok;
  ctx.tally->error_replies += r.errors;
  if (r.ok + r.errors < sent)
    ctx.tally->problem(std::to_string(sent - r.ok - r.errors) + " of " + std::to_string(sent) +
                       " control messages unanswered" +
                       (r.connection_ended ? " (connection ended)" : ""));
  if (r.ok > valid) ctx.tally->problem("an invalid control message was accepted");
}

}  // namespace

void run_stormer(WorkerContext ctx) {
  Rng rng(ctx.seed);
  while (Clock::now() < ctx.until) {
    try {
      WsClient c(ctx.port);
      ++ctx.tally->ws_connections;
      while (Clock::now() < ctx.until) {
        storm_burst(ctx, rng, c);
        if (chance(rng, 0.03)) {
          if (!closed_as_too_big(c)) ctx.tally->problem("a 100 KiB message did not close");
          ++ctx.tally->too_big_closes;
          break;  // reconnect
        }
        read_and_ack(c, Clock::now() + random_ms(rng, 0, 300), *ctx.tally, false);
      }
    } catch (const std::exception& e) {
      ctx.tally->problem(std::string("storm: ") + e.what());
    }
  }
}

namespace {

// The director's messages: only valid ones, each one a global change every client sees.
std::vector<json> director_action(Rng& rng, const Catalog& catalog, Tally& tally,
                                  bool& reference_on) {
  const auto& sizes = soak_sizes();
  const Size& size = sizes[static_cast<std::size_t>(uniform_int(rng, 0, int(sizes.size()) - 1))];
  const json resolution = {
      {"type", "set_resolution"}, {"width", size.width}, {"height", size.height}};
  const int roll = uniform_int(rng, 1, 100);
  if (roll <= 30) {  // a scene comes at its own size: choose ours in the same breath
    ++tally.scene_changes;
    const auto& scene =
        catalog
            .scenes[static_cast<std::size_t>(uniform_int(rng, 0, int(catalog.scenes.size()) - 1))];
    return {{{"type", "set_scene"}, {"name", scene}}, resolution};
  }
  if (roll <= 55) {
    ++tally.resolution_changes;
    return {resolution};
  }
  if (roll <= 80) {
    ++tally.reference_toggles;
    reference_on = !reference_on;
    return {{{"type", "reference"}, {"on", reference_on}}};
  }
  const auto& method =
      catalog
          .methods[static_cast<std::size_t>(uniform_int(rng, 0, int(catalog.methods.size()) - 1))];
  return {{{"type", "set_method"}, {"method", method}}};
}

// Every reply ok, except "server busy" (the stormers may fill the 64-command queue).
void check_all_ok(const Replies& r, std::size_t expected, Tally& tally, const char* who) {
  if (r.ok + r.errors < static_cast<long>(expected))
    tally.problem(std::string(who) + ": a valid message unanswered");
  for (const auto& e : r.error_texts)
    if (e.find("busy") == std::string::npos)
      tally.problem(std::string(who) + ": a valid message refused: " + e);
}

}  // namespace

void run_director(WorkerContext ctx) {
  Rng rng(ctx.seed);
  bool reference_on = false;
  try {
    WsClient c(ctx.port);
    ++ctx.tally->ws_connections;
    while (Clock::now() < ctx.until) {
      read_and_ack(c, Clock::now() + random_ms(rng, 500, 2000), *ctx.tally, false);
      const auto messages = director_action(rng, *ctx.catalog, *ctx.tally, reference_on);
      for (const auto& m : messages) c.send_json(m);
      ctx.tally->valid_sent += static_cast<long>(messages.size());
      const Replies r = await_replies(c, static_cast<long>(messages.size()), 30s);
      ctx.tally->ok_replies += r.ok;
      ctx.tally->error_replies += r.errors;
      check_all_ok(r, messages.size(), *ctx.tally, "director");
    }
    c.close();
  } catch (const std::exception& e) {
    ctx.tally->problem(std::string("director: ") + e.what());
  }
}

void run_stall_keeper(WorkerContext ctx) {
  Rng rng(ctx.seed);
  while (Clock::now() < ctx.until) {
    try {
      // A tiny receive buffer: the server's writes stall as soon as the kernel's buffers fill.
      WsClient s(ctx.port, "", "", 4096);
      ++ctx.tally->ws_connections;
      ++ctx.tally->stalled;
      if (chance(rng, 0.3)) s.send(random_valid_message(rng, *ctx.catalog).text);  // a reply too
      // Past the 5 s deadline and the 250 ms watchdog: the server must have cut it off.
      std::this_thread::sleep_for(random_ms(rng, 6000, 8000));
      if (drained_to_end(s, 15s))
        ++ctx.tally->stalled_cut_off;
      else
        ctx.tally->problem("a stalled client was not cut off by the deadline");
    } catch (const std::exception& e) {
      ctx.tally->problem(std::string("stall: ") + e.what());
    }
  }
}

std::string reset_settings(unsigned short port) {
  const std::vector<json> messages = {
      {{"type", "reference"}, {"on", false}},
      {{"type", "set_scene"}, {"name", "teapot"}},
      {{"type", "set_method"}, {"method", "kb-adaptive"}},
      {{"type", "set_resolution"}, {"width", 320}, {"height", 240}}};
  try {
    WsClient c(port);
    for (const auto& m : messages) {
      c.send_json(m);
      const Replies r = await_replies(c, 1, 30s);
      if (r.ok != 1)
        return m.dump() + ": " + (r.error_texts.empty() ? "no reply" : r.error_texts[0]);
    }
    c.close();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// --- the observer --------------------------------------------------------------------------------

Observer::Observer(unsigned short port) : client_(std::make_unique<WsClient>(port)) {
  const json state = client_->read_json("state", 10s);
  if (!state.is_object()) throw std::runtime_error("observer: no state message");
  catalog_.methods = state["methods"].get<std::vector<std::string>>();
  catalog_.scenes = state["scenes"].get<std::vector<std::string>>();
  thread_ = std::thread([this] { run(); });
}

Observer::~Observer() { stop(); }

void Observer::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void Observer::run() {
  try {
    read_until_stopped();
  } catch (const std::exception& e) {
    std::lock_guard lk(m_);
    failure_ = std::string("observer: ") + e.what();
  }
}

void Observer::read_until_stopped() {
  while (!stop_) {
    Message m = client_->read(200ms);
    if (m.ec == net::error::timed_out) continue;
    if (!m.ok) {
      std::lock_guard lk(m_);
      failure_ = "observer disconnected: " + m.ec.message();
      return;
    }
    const auto now = Clock::now();
    if (m.binary) {
      client_->ack(m.data);
      const auto header = frame_header(m.data);
      if (header && header->kind == tp::server::FrameKind::device) {
        std::lock_guard lk(m_);
        frames_.push_back({now, header->render_ms, header->id});
      }
      continue;
    }
    const json j = json::parse(m.data, nullptr, false);
    if (j.is_object() && j.value("type", "") == "stats") {
      std::lock_guard lk(m_);
      const std::uint32_t published =
          j.contains("frame") ? j["frame"].value("id", std::uint32_t{0}) : 0;
      stats_.push_back({now, j.value("fps", 0.0), j.value("clients", -1L), published,
                        j.value("frames_rendered", std::uint64_t{0}), j.value("render_ms", 0.0)});
    }
  }
}

std::vector<FrameArrival> Observer::frames() const {
  std::lock_guard lk(m_);
  return frames_;
}

std::vector<StatsSample> Observer::stats() const {
  std::lock_guard lk(m_);
  return stats_;
}

std::string Observer::failure() const {
  std::lock_guard lk(m_);
  return failure_;
}

}  // namespace tpt::soak
