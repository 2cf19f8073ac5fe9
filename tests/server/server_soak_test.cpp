// The server soak test (docs/SERVER.md, "Soak test"): the real tinyphong-server (the device,
// not the test pattern) on a free loopback port, for TP_SOAK_SECONDS (default: the build's, 180
// in dev, 60 under the sanitizers), through phases of random connects and disconnects, control
// message storms, scene / resolution / method / reference changes and stalled clients, while
// one steady client watches the frames. Passes when the server's open descriptors come back
// exactly to the baseline, its memory to within a bound, and no reading client waited longer
// than a bound for a frame. TP_SOAK_SEED replays the clients' choices of a run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <numeric>

#include "soak_clients.hpp"

using namespace tpt;
using namespace tpt::soak;

namespace {

// --- bounds (docs/SERVER.md, "Soak test", gives the measurements they come from) ---------------

// The steady client may wait no longer than this for a frame once the server has said (in a
// "stats" message) that a newer one was published, and no longer than this for any message.
// Measured (Debug, 2 shared cores): without storms at most 65 ms between frames; with storms,
// before the render loop paced its commands (RenderLoop::apply_pending), the frames stopped for
// 1.7-5.2 s beyond their render time, which this bound catches.
constexpr double kMaxFrameOverheadMs = 3000;
#ifdef TP_SOAK_UNDER_SANITIZERS
// ASan's allocator keeps freed memory in its quarantine and per-thread caches: measured +15.5
// MiB after and +26.7 MiB at the peak in a 60 s run, which is allocator behaviour, not a leak
// (LeakSanitizer checks leaks at the server's exit; the dev build checks growth).
constexpr long kRssReturnKiB = 48 * 1024;
constexpr long kRssPeakKiB = 96 * 1024;
#else
// After the storm, the server's resident memory within this of the baseline. Measured: +1.0
// MiB (60 s), +3.0 MiB (180 s), +0.0 MiB (540 s, every quiet point within +0.6 MiB); later
// +3.6 to +8.4 MiB (180 s, seeds 3972872195 and 1039929008), glibc's dynamic mmap threshold
// leaving holes in the threads' heaps; with the server's fixed threshold +0.2 and -0.1 MiB for
// the same seeds (docs/SERVER.md, "Found and fixed").
constexpr long kRssReturnKiB = 8 * 1024;
// During the storm, never more than this above the baseline (stalled clients included).
// Measured peaks: +1.7, +4.0 and +6.8 MiB in the same runs.
constexpr long kRssPeakKiB = 24 * 1024;
#endif

// --- configuration
// ---------------------------------------------------------------------------------

struct SoakConfig {
  double seconds;
  std::uint64_t seed;
  double phase_seconds;
};

SoakConfig read_config() {
  SoakConfig c{};
  const char* s = std::getenv("TP_SOAK_SECONDS");
  c.seconds = s ? std::atof(s) : TP_SOAK_DEFAULT_SECONDS;
  const char* seed = std::getenv("TP_SOAK_SEED");
  c.seed = seed ? std::strtoull(seed, nullptr, 10) : std::random_device{}();
  // About ten phases a run, each long enough for a stalled client's 5 s deadline to pass.
  c.phase_seconds = std::clamp(c.seconds / 10, 6.0, 30.0);
  return c;
}

std::uint64_t worker_seed(std::uint64_t seed, std::size_t phase, int worker) {
  return seed + 0x9E3779B97F4A7C15ull * (phase * 64 + static_cast<std::uint64_t>(worker) + 1);
}

// --- phases
// ----------------------------------------------------------------------------------------

enum class PhaseKind { warmup, churn, storm, stall, mixed };

const char* to_string(PhaseKind k) {
  switch (k) {
    case PhaseKind::warmup: return "warm-up (all)";
    case PhaseKind::churn: return "churn";
    case PhaseKind::storm: return "storm + changes";
    case PhaseKind::stall: return "stalled + churn";
    case PhaseKind::mixed: return "all at once";
  }
  return "?";
}

struct Phase {
  PhaseKind kind;
  Clock::time_point start, end;
  std::unique_ptr<Tally> tally = std::make_unique<Tally>();
};

// Which clients a phase runs: churners, stormers, the director, the stall keeper.
std::vector<std::thread> start_workers(PhaseKind kind, const WorkerContext& base,
                                       std::uint64_t seed, std::size_t phase_index) {
  const bool all = kind == PhaseKind::warmup || kind == PhaseKind::mixed;
  std::vector<std::thread> workers;
  int w = 0;
  auto launch = [&](void (*run)(WorkerContext)) {
    WorkerContext ctx = base;
    ctx.seed = worker_seed(seed, phase_index, w++);
    workers.emplace_back(run, ctx);
  };
  if (all || kind == PhaseKind::churn || kind == PhaseKind::stall)
    for (int i = 0; i < 4; ++i) launch(run_churner);
  if (all || kind == PhaseKind::storm) {
    for (int i = 0; i < 2; ++i) launch(run_stormer);
    launch(run_director);
  }
  if (all || kind == PhaseKind::stall) launch(run_stall_keeper);
  return workers;
}

// --- sampling
// ----------------------------------------------------------------------------------------

struct Sample {
  Clock::time_point at;
  long rss_kib;
  int fds;
};

// Samples the server's RSS and open descriptors every 100 ms on its own thread.
class Sampler {
 public:
  explicit Sampler(ServerProcess& srv) : thread_([this, &srv] { run(srv); }) {}
  ~Sampler() {
    stop_ = true;
    thread_.join();
  }
  std::vector<Sample> samples() const {
    std::lock_guard lk(m_);
    return samples_;
  }
  bool server_died() const { return died_; }

 private:
  void run(ServerProcess& srv) {
    while (!stop_) {
      if (!srv.running()) {
        died_ = true;
        return;
      }
      const Sample s{Clock::now(), srv.rss_kib(), srv.fd_count()};
      {
        std::lock_guard lk(m_);
        samples_.push_back(s);
      }
      std::this_thread::sleep_for(100ms);
    }
  }
  mutable std::mutex m_;
  std::vector<Sample> samples_;
  std::atomic<bool> stop_{false}, died_{false};
  std::thread thread_;
};

std::vector<Sample> between(const std::vector<Sample>& all, Clock::time_point a,
                            Clock::time_point b) {
  std::vector<Sample> out;
  for (const auto& s : all)
    if (s.at >= a && s.at <= b) out.push_back(s);
  return out;
}

// --- quiet points: nothing running but the observer
// -------------------------------------------------

struct Quiet {
  long rss_kib = 0;  // mean over the last 2 s
  int fds = 0;
  long clients = -1;  // as the server's last stats said
};

long latest_clients(const Observer& observer) {
  const auto stats = observer.stats();
  return stats.empty() ? -1 : stats.back().clients;
}

// Waits until the descriptors equal `target` (or, with no target, stay the same for 2 s) and
// the server counts the observer alone; then averages the RSS over 2 s.
Quiet settle(const Sampler& sampler, const Observer& observer, std::optional<int> target) {
  const auto give_up = Clock::now() + 30s;
  int last = -1;
  auto stable_since = Clock::now();
  while (Clock::now() < give_up && !sampler.server_died()) {
    std::this_thread::sleep_for(250ms);
    const auto samples = sampler.samples();
    if (samples.empty()) continue;
    const int fds = samples.back().fds;
    if (fds != last) stable_since = Clock::now();
    last = fds;
    const bool fds_done = target ? fds == *target : Clock::now() - stable_since >= 2s;
    if (fds_done && latest_clients(observer) == 1) break;
  }
  const auto t0 = Clock::now();
  std::this_thread::sleep_for(2s);
  const auto window = between(sampler.samples(), t0, Clock::now());
  Quiet q;
  for (const auto& s : window) q.rss_kib += s.rss_kib;
  q.rss_kib = window.empty() ? -1 : q.rss_kib / static_cast<long>(window.size());
  q.fds = window.empty() ? -1 : window.back().fds;
  q.clients = latest_clients(observer);
  return q;
}

// --- figures
// -----------------------------------------------------------------------------------------

struct Figures {
  double seconds = 0, observer_fps = 0, server_fps_min = 0, server_fps_mean = 0;
  Gaps observer, readers;
  long rss_peak_kib = 0;
  int fds_peak = 0;
};

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// The observer's worst gaps among those that ended in [a, b] (a gap belongs to the frame that
// ended it, wherever the previous frame fell). The wait that counts against the server starts
// when a "stats" message said a newer frame had been published: the render loop does not
// re-send identical frames (a sphere at 16x16 may look the same for seconds), and the device's
// render time is the storm's choice of method, lights and size.
Gaps gaps_ending_in(const std::vector<FrameArrival>& frames, const std::vector<StatsSample>& stats,
                    Clock::time_point a, Clock::time_point b) {
  Gaps g;
  std::size_t s = 0;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const FrameArrival &prev = frames[i - 1], &cur = frames[i];
    while (s < stats.size() && stats[s].at <= prev.at) ++s;
    if (cur.at < a || cur.at > b) continue;
    g.gap_ms = std::max(g.gap_ms, ms(cur.at - prev.at));
    for (std::size_t k = s; k < stats.size() && stats[k].at < cur.at; ++k) {
      if (stats[k].published_id > prev.id) {
        g.overhead_ms = std::max(g.overhead_ms, ms(cur.at - stats[k].at));
        break;
      }
    }
  }
  return g;
}

// The longest silence between two "stats" messages (about 4 Hz, whatever the frames do): a
// blocked I/O thread or a starved session shows here.
double max_stats_gap_ms(const std::vector<StatsSample>& stats, Clock::time_point end) {
  double worst = 0;
  for (std::size_t i = 1; i < stats.size(); ++i)
    worst = std::max(worst, ms(stats[i].at - stats[i - 1].at));
  if (!stats.empty()) worst = std::max(worst, ms(end - stats.back().at));
  return worst;
}

// The render loop's longest stall: the time between two "stats" messages that saw its count of
// rendered frames go up, less the render time of the frame that ended it (a frame may take
// seconds to render in a Debug build: teapot-l8 with exact Phong). Frames are rendered whatever
// the clients do (the animation runs through the whole soak), so a loop held back — by control
// messages, a lock or a blocked publish — shows here even where identical frames are not sent.
double max_render_stall_ms(const std::vector<StatsSample>& stats) {
  double worst = 0;
  std::size_t last_rise = 0;
  for (std::size_t i = 1; i < stats.size(); ++i) {
    if (stats[i].frames_rendered <= stats[i - 1].frames_rendered) continue;
    worst = std::max(worst, ms(stats[i].at - stats[last_rise].at) - stats[i].render_ms);
    last_rise = i;
  }
  return worst;
}

Figures figures_of(const Phase& p, const std::vector<Sample>& samples, const Observer& observer) {
  Figures f;
  f.seconds = ms(p.end - p.start) / 1000;
  const auto frames = observer.frames();
  const auto n = std::count_if(frames.begin(), frames.end(),
                               [&](const auto& fr) { return fr.at >= p.start && fr.at <= p.end; });
  f.observer_fps = static_cast<double>(n) / f.seconds;
  f.observer = gaps_ending_in(frames, observer.stats(), p.start, p.end);
  f.readers = {static_cast<double>(p.tally->reader_max_gap_us.load()) / 1000,
               static_cast<double>(p.tally->reader_max_overhead_us.load()) / 1000};
  std::vector<double> fps;
  for (const auto& s : observer.stats())
    if (s.at >= p.start && s.at <= p.end) fps.push_back(s.fps);
  if (!fps.empty()) {
    f.server_fps_min = *std::min_element(fps.begin(), fps.end());
    f.server_fps_mean = std::accumulate(fps.begin(), fps.end(), 0.0) / double(fps.size());
  }
  for (const auto& s : between(samples, p.start, p.end)) {
    f.rss_peak_kib = std::max(f.rss_peak_kib, s.rss_kib);
    f.fds_peak = std::max(f.fds_peak, s.fds);
  }
  return f;
}

void print_phase(const Phase& p, const Figures& f) {
  const Tally& t = *p.tally;
  std::printf(
      "| %-16s | %5.1f | %4ld ws + %3ld http + %3ld raw | %5ld / %5ld | %5ld / %5ld | %2ld / %2ld "
      "/ %2ld | %2ld (%2ld) | %5.1f | %5.1f-%5.1f | %5.0f (%4.0f) | %5.0f (%4.0f) | %6.1f | %3d "
      "|\n",
      to_string(p.kind), f.seconds, t.ws_connections.load(), t.http_requests.load(),
      t.raw_connections.load(), t.valid_sent.load(), t.invalid_sent.load(), t.ok_replies.load(),
      t.error_replies.load(), t.scene_changes.load(), t.resolution_changes.load(),
      t.reference_toggles.load(), t.stalled.load(), t.stalled_cut_off.load(), f.observer_fps,
      f.server_fps_min, f.server_fps_mean, f.observer.gap_ms, f.observer.overhead_ms,
      f.readers.gap_ms, f.readers.overhead_ms, double(f.rss_peak_kib) / 1024, f.fds_peak);
}

void print_header() {
  std::printf(
      "| phase | s | connections | control valid / invalid | replies ok / error | scene / size "
      "/ reference changes | stalled (cut off) | observer frames/s | server fps min-mean | "
      "observer's worst gap (after a newer frame was published) ms | churning readers' worst gap "
      "(less render) ms | "
      "peak RSS MiB | peak fds |\n");
}

// The server's stderr, counted by what failed ("websocket read: End of file" -> 1 more).
void print_stderr_summary(const std::string& path) {
  std::ifstream f(path);
  std::map<std::string, long> counts;
  for (std::string line; std::getline(f, line);) ++counts[line.substr(0, 80)];
  std::printf("[ soak ] server stderr (%zu kinds of line):\n", counts.size());
  for (const auto& [line, n] : counts) std::printf("  %7ld  %s\n", n, line.c_str());
}

}  // namespace

TEST(ServerSoak, ChurnStormsStallsAndChangesComeBackToBaseline) {
  const SoakConfig cfg = read_config();
  std::printf(
      "[ soak ] seed %llu (TP_SOAK_SEED=%llu replays the clients' choices), %.0f s, "
      "phases of %.0f s\n",
      static_cast<unsigned long long>(cfg.seed), static_cast<unsigned long long>(cfg.seed),
      cfg.seconds, cfg.phase_seconds);
  const std::string err_path = ::testing::TempDir() + "tinyphong_soak_server_stderr.txt";
  ServerProcess srv(
      {"--scene", "teapot", "--method", "kb-adaptive", "--width", "320", "--height", "240"},
      err_path);
  Sampler sampler(srv);
  Observer observer(srv.port());
  const Catalog catalog = observer.catalog();
  const auto run_start = Clock::now();
  const auto run_end = run_start + std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>(cfg.seconds));
  const auto phase_len =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(cfg.phase_seconds));
  std::vector<Phase> phases;
  auto run_phase = [&](PhaseKind kind) {
    Phase p{kind, Clock::now(), {}};
    const WorkerContext base{srv.port(), &catalog, p.start + phase_len, p.tally.get(), 0};
    for (auto& w : start_workers(kind, base, cfg.seed, phases.size())) w.join();
    p.end = Clock::now();
    phases.push_back(std::move(p));
  };
  auto reset = [&] {
    const std::string why = reset_settings(srv.port());
    EXPECT_EQ(why, "") << "resetting the settings";
  };

  run_phase(PhaseKind::warmup);
  reset();
  const Quiet baseline = settle(sampler, observer, std::nullopt);
  std::printf("[ soak ] baseline: RSS %.1f MiB, %d fds, %ld client\n",
              double(baseline.rss_kib) / 1024, baseline.fds, baseline.clients);
  const PhaseKind cycle[] = {PhaseKind::churn, PhaseKind::storm, PhaseKind::stall,
                             PhaseKind::mixed};
  // Keep ~10 s for the final quiet point within the budget; at least one full cycle. Between
  // cycles a quiet point too, so that a long run shows whether memory keeps growing.
  std::vector<Quiet> quiet_points;
  for (std::size_t i = 0; i < 4 || Clock::now() + phase_len + 10s < run_end; ++i) {
    if (sampler.server_died()) break;
    if (i > 0 && i % 4 == 0) {
      reset();
      quiet_points.push_back(settle(sampler, observer, baseline.fds));
    }
    run_phase(cycle[i % 4]);
  }
  reset();
  quiet_points.push_back(settle(sampler, observer, baseline.fds));
  const Quiet& final_point = quiet_points.back();
  const auto run_stop = Clock::now();
  observer.stop();

  const auto samples = sampler.samples();
  print_header();
  long peak_rss = 0;
  Gaps readers;
  for (const auto& p : phases) {
    const Figures f = figures_of(p, samples, observer);
    print_phase(p, f);
    if (p.kind != PhaseKind::warmup) peak_rss = std::max(peak_rss, f.rss_peak_kib);
    readers.gap_ms = std::max(readers.gap_ms, f.readers.gap_ms);
    readers.overhead_ms = std::max(readers.overhead_ms, f.readers.overhead_ms);
    for (const auto& problem : p.tally->problems())
      ADD_FAILURE() << to_string(p.kind) << ": " << problem;
  }
  // Every gap of the run, the quiet points included, and the wait after the last frame.
  const auto frames = observer.frames();
  const Gaps observed = gaps_ending_in(frames, observer.stats(), run_start, run_stop);
  const double stats_gap = max_stats_gap_ms(observer.stats(), run_stop);
  const double render_stall = max_render_stall_ms(observer.stats());
  for (std::size_t i = 0; i < quiet_points.size(); ++i)
    std::printf("[ soak ] quiet point %zu: RSS %.1f MiB, %d fds, %ld client\n", i + 1,
                double(quiet_points[i].rss_kib) / 1024, quiet_points[i].fds,
                quiet_points[i].clients);
  std::printf(
      "[ soak ] after: RSS %.1f MiB (baseline %.1f, peak %.1f), %d fds (baseline %d), %ld "
      "client; worst frame gap %.0f ms, %.0f ms after a newer frame was published (observer), "
      "%.0f ms, %.0f ms beyond the render (churning readers); stats silent for at most %.0f ms; "
      "render loop stalled for at most %.0f ms beyond a frame's render; %zu frames observed; %.0f "
      "s in all\n",
      double(final_point.rss_kib) / 1024, double(baseline.rss_kib) / 1024, double(peak_rss) / 1024,
      final_point.fds, baseline.fds, final_point.clients, observed.gap_ms, observed.overhead_ms,
      readers.gap_ms, readers.overhead_ms, stats_gap, render_stall, frames.size(),
      ms(run_stop - run_start) / 1000);
  print_stderr_summary(err_path);

  ASSERT_FALSE(sampler.server_died()) << "the server died: status " << srv.exit_status();
  EXPECT_EQ(observer.failure(), "");
  for (const auto& q : quiet_points) {
    EXPECT_EQ(q.fds, baseline.fds) << "open descriptors back to the baseline";
    EXPECT_EQ(q.clients, 1) << "the server still counts other clients";
  }
  EXPECT_LE(final_point.rss_kib - baseline.rss_kib, kRssReturnKiB) << "RSS back near baseline";
  EXPECT_LE(peak_rss - baseline.rss_kib, kRssPeakKiB) << "RSS during the storm";
  EXPECT_LE(observed.overhead_ms, kMaxFrameOverheadMs) << "the observer's worst frame delay";
  EXPECT_LE(stats_gap, kMaxFrameOverheadMs) << "the observer's longest silence";
  EXPECT_LE(render_stall, kMaxFrameOverheadMs) << "the render loop's longest stall";
  // The server ends cleanly too (under the sanitizers, LeakSanitizer runs at this exit).
  std::chrono::milliseconds took{};
  const int status = srv.signal_and_wait(SIGTERM, 5000ms, took);
  EXPECT_TRUE(status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << "exit status " << status << " after SIGTERM";
}
