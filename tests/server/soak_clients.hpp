// The clients of the server soak test (docs/SERVER.md, "Soak test"), each a loop on its own
// thread until a deadline, every wait bounded: churners (random connects and disconnects of
// every kind), stormers (bursts of valid and invalid control messages), the director (scene,
// resolution, method and reference changes), the stall keeper (clients that stop reading), and
// the observer (one steady client for the whole run, whose frame times give the frame gaps).
#pragma once
#include <utility>  // before Boost 1.74 asio (awaitable.hpp uses std::exchange)

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server_process.hpp"
#include "soak_messages.hpp"

namespace tpt::soak {

using Clock = std::chrono::steady_clock;

// What the clients of one phase did and saw, written by many threads.
struct Tally {
  std::atomic<long> ws_connections{0}, http_requests{0}, raw_connections{0};
  std::atomic<long> valid_sent{0}, invalid_sent{0}, ok_replies{0}, error_replies{0};
  std::atomic<long> too_big_closes{0};
  std::atomic<long> scene_changes{0}, resolution_changes{0}, reference_toggles{0};
  std::atomic<long> stalled{0}, stalled_cut_off{0};
  std::atomic<long> reader_frames{0};
  // A churning reader's worst wait between two device frames, and the worst of that wait less
  // the device's render time of the frame that ended it (the server's own share).
  std::atomic<long long> reader_max_gap_us{0}, reader_max_overhead_us{0};
  // A client-side surprise (a handshake refused, a reply missing, an invalid message accepted,
  // a stalled client left open...): each one fails the test, named.
  void problem(const std::string& what);
  std::vector<std::string> problems() const;

 private:
  mutable std::mutex m_;
  std::vector<std::string> problems_;
};

struct WorkerContext {
  unsigned short port;
  const Catalog* catalog;
  Clock::time_point until;  // no new action starts after this
  Tally* tally;
  std::uint64_t seed;
};

void run_churner(WorkerContext ctx);
void run_stormer(WorkerContext ctx);
void run_director(WorkerContext ctx);
void run_stall_keeper(WorkerContext ctx);

// Puts the server back to the settings of the baseline (teapot, kb-adaptive, 320x240, four
// lights' worth of storm edits undone by the scene reload, reference off); empty or why not.
std::string reset_settings(unsigned short port);

// One device frame as a client saw it: when it arrived, and how long the device took for it
// (from the frame's header).
struct FrameArrival {
  Clock::time_point at;
  double render_ms;
  std::uint32_t id;
};

// The worst wait between consecutive frames, and the worst wait less the render time of the
// frame that ended it, in ms.
struct Gaps {
  double gap_ms = 0, overhead_ms = 0;
};

struct StatsSample {
  Clock::time_point at;
  double fps;
  long clients;
  std::uint32_t published_id;     // the last device frame the server had published
  std::uint64_t frames_rendered;  // the render loop's count of frames rendered
  double render_ms;               // the last frame's render time
};

// The steady client: connected for the whole run, acks every frame like the page, records
// when each device frame arrived and every "stats" message.
class Observer {
 public:
  explicit Observer(unsigned short port);  // throws if the first "state" does not come
  ~Observer();
  const Catalog& catalog() const { return catalog_; }
  std::vector<FrameArrival> frames() const;
  std::vector<StatsSample> stats() const;
  std::string failure() const;  // why its connection ended, empty while it is open
  void stop();

 private:
  void run();
  void read_until_stopped();
  std::unique_ptr<WsClient> client_;
  Catalog catalog_;
  std::atomic<bool> stop_{false};
  mutable std::mutex m_;
  std::vector<FrameArrival> frames_;
  std::vector<StatsSample> stats_;
  std::string failure_;
  std::thread thread_;
};

}  // namespace tpt::soak
