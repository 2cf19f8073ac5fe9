// Measurement tool for docs/SERVER.md (not a test): connects N reading clients (each acks every
// frame, like the page) and optionally stalled clients (handshake, then never read) to a running
// tinyphong-server, for T seconds; reports frames/s and bytes per frame per client, the server's
// RSS (given its pid), and what zlib would save on the frames (lossless compression check).
//   server_loadgen --port P [--clients N] [--stalled K] [--seconds T] [--pid PID]
#include <zlib.h>
#include <utility>  // before Boost 1.74 asio (awaitable.hpp uses std::exchange)

#include <atomic>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "server/protocol.hpp"
#define TP_SERVER_BINARY ""
#include "server_process.hpp"

using namespace tpt;
using Clock = std::chrono::steady_clock;

namespace {
long rss_kib(int pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  std::string k;
  long v = -1;
  while (f >> k)
    if (k == "VmRSS:") f >> v;
  return v;
}
}  // namespace

int main(int argc, char** argv) {
  unsigned short port = 0;
  int clients = 1, stalled = 0, pid = 0;
  double seconds = 10;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const std::string v = argv[i + 1];
    if (k == "--port")
      port = static_cast<unsigned short>(std::stoi(v));
    else if (k == "--clients")
      clients = std::stoi(v);
    else if (k == "--stalled")
      stalled = std::stoi(v);
    else if (k == "--seconds")
      seconds = std::stod(v);
    else if (k == "--pid")
      pid = std::stoi(v);
  }
  if (!port) {
    std::fprintf(
        stderr,
        "usage: server_loadgen --port P [--clients N] [--stalled K] [--seconds T] [--pid PID]\n");
    return 2;
  }
  const long rss0 = pid ? rss_kib(pid) : -1;
  std::vector<std::unique_ptr<WsClient>> stall;
  for (int i = 0; i < stalled; ++i) stall.push_back(std::make_unique<WsClient>(port, "", "", 4096));
  std::atomic<long long> frames{0}, bytes{0};
  std::atomic<long> rss_max{0};
  std::mutex sample_m;
  std::string sample, stats;
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(seconds));
  std::vector<std::thread> threads;
  for (int i = 0; i < clients; ++i) {
    threads.emplace_back([&, i] {
      WsClient c(port);
      while (Clock::now() < end) {
        Message m =
            c.read(std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()) + 1ms);
        if (!m.ok) break;
        if (!m.binary) {
          if (i == 0 && m.data.find("\"stats\"") != std::string::npos) {
            std::lock_guard lk(sample_m);
            stats = m.data;
          }
          continue;
        }
        c.ack(m.data);
        ++frames;
        bytes += static_cast<long long>(m.data.size());
        if (i == 0) {
          std::lock_guard lk(sample_m);
          sample = m.data;
        }
      }
    });
  }
  while (Clock::now() < end) {
    if (pid) rss_max = std::max(rss_max.load(), rss_kib(pid));
    std::this_thread::sleep_for(200ms);
  }
  for (auto& t : threads) t.join();
  const double per_client_fps = static_cast<double>(frames) / clients / seconds;
  std::printf("clients %d (+%d stalled), %.1f s: %.2f frames/s per client, %.0f bytes per frame\n",
              clients, stalled, seconds, per_client_fps,
              frames ? static_cast<double>(bytes) / static_cast<double>(frames) : 0.0);
  if (!stats.empty()) {
    auto j = nlohmann::json::parse(stats);
    std::printf("server stats: render loop %.2f fps, device render %.2f ms/frame, %d clients\n",
                j["fps"].get<double>(), j["render_ms"].get<double>(), j["clients"].get<int>());
  }
  if (pid) std::printf("server RSS: %ld KiB before, %ld KiB max during\n", rss0, rss_max.load());
  tp::server::EncodedFrame header;
  if (tp::server::decode_header(
          {reinterpret_cast<const std::uint8_t*>(sample.data()), sample.size()}, header)) {
    const auto* px = reinterpret_cast<const Bytef*>(sample.data() + header.header_bytes);
    const uLong n = static_cast<uLong>(sample.size() - header.header_bytes);
    for (int level : {1, 6}) {
      std::vector<Bytef> out(compressBound(n));
      uLongf outn = static_cast<uLongf>(out.size());
      const auto t0 = Clock::now();
      compress2(out.data(), &outn, px, n, level);
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      std::printf("zlib level %d on one frame: %lu -> %lu bytes (%.1f%%) in %.2f ms\n", level, n,
                  static_cast<unsigned long>(outn),
                  100.0 * static_cast<double>(outn) / static_cast<double>(n), ms);
    }
  }
  return 0;
}
