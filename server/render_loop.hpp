// The render loop: its own thread runs the device continuously and publishes each new frame
// into the hub's "latest" slot; it never waits for a client. Control commands are queued and
// applied between frames. The double reference runs on a second worker thread (latest-only),
// never in the render loop.
#pragma once
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "server/control.hpp"
#include "server/frame_source.hpp"
#include "server/hub.hpp"

namespace tp::server {

struct LoopOptions {
  double max_fps = 60;              // pacing cap, so an idle viewer does not burn a core
  double radians_per_second = 0.6;  // animated model rotation
  std::size_t max_pending_commands = 64;
};

// What the page shows of the device frame against the double reference (docs/SERVER.md, the
// "stats" message): host::compare's measures over the pixels covered in both images — colour
// correctness (Vlasic's thesis, chapter 6, eq. 6.1), level errors, PSNR — the same convention
// as the desktop tools' figures in docs/RESULTS.md.
struct ErrorStats {
  std::uint32_t frame_id = 0;
  std::size_t pixels = 0;
  double correctness = 1, mean_levels = 0, max_levels = 0;
  // In dB. JSON has no infinity, so where host::compare gives +inf (identical images) the page
  // gets 99; with no pixel covered in both (or images of different sizes) it gets 0.
  double psnr = 0;
};
ErrorStats compare_images(const Image& device, const Image& reference);

class RenderLoop {
 public:
  RenderLoop(std::unique_ptr<FrameSource> src, Hub& hub, LoopOptions opt);
  ~RenderLoop();
  void start();
  void stop();
  // done gets the outcome of applying the command, on the render-loop thread.
  using Done = std::function<void(const Result& outcome)>;
  Result submit(Command c, Done done);  // fails when the command queue is full
  TextPtr state_message();
  std::string stats_message(std::size_t clients);

 private:
  struct Job {
    Command cmd;
    Done done;
  };
  struct RefJob {
    std::function<Image()> task;
    std::uint32_t frame_id;
    Image device;
  };
  struct LastFrame {
    double rotation;
    std::uint32_t frame_id;
    Image device;
  };
  // "compare all methods" (docs/SERVER.md): the frame on screen when it was asked for, rendered
  // with every registered method against one double reference, one method per loop iteration so
  // that the stream goes on between them; a settings change abandons it.
  struct CompareRow {
    std::string method;
    ErrorStats error;
    double ms = 0;      // the fastest of kCompareRenders renders of the frame
    std::string fault;  // set when the source refused the method
  };
  struct CompareJob {
    double rotation = 0;
    std::vector<std::string> methods;
    std::optional<Image> reference;
    std::vector<CompareRow> rows;
  };
  static constexpr int kCompareRenders = 3;
  void start_compare();
  void compare_step();
  void abandon_compare(const std::string& why);
  void publish_compare_progress(const char* method);
  void publish_comparison();

  void run();
  std::optional<Job> next_job();  // the oldest queued command, if any
  bool apply_pending();           // true if anything changed
  void render_and_publish(double rotation);
  void publish_state();
  void offer_reference();
  void ref_run();

  std::unique_ptr<FrameSource> src_;
  Hub& hub_;
  LoopOptions opt_;
  std::thread thread_, ref_thread_;
  std::mutex m_;  // guards jobs_, running_, stats and the state message
  std::condition_variable cv_;
  std::deque<Job> jobs_;
  bool running_ = false;
  TextPtr state_;
  // Render-loop-thread only.
  LoopFlags flags_;
  bool step_ = false, dirty_ = true;
  double rotation_ = 0;
  std::uint32_t next_id_ = 1;
  std::uint64_t last_checksum_ = 0;
  int last_w_ = 0, last_h_ = 0;
  std::optional<LastFrame> last_;  // the last published device frame, for a late reference request
  std::optional<CompareJob> compare_;
  // Stats (under m_).
  double fps_ = 0, render_ms_ = 0, loop_ms_ = 0;
  std::uint64_t frames_rendered_ = 0, frames_published_ = 0;
  std::vector<std::pair<std::string, std::uint64_t>> counters_;
  std::uint32_t frame_id_ = 0;
  std::uint64_t frame_checksum_ = 0;
  std::optional<ErrorStats> error_;
  // Why the device refused the last frame the loop tried (none once one renders again).
  std::optional<std::string> refused_;
  bool reference_on_ = false;
  // Reference worker.
  std::mutex rm_;
  std::condition_variable rcv_;
  std::optional<RefJob> ref_job_;
  bool ref_running_ = false;
};

}  // namespace tp::server
