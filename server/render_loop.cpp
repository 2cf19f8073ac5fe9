#include "server/render_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "firmware/cosn.hpp"
#include "host/metrics.hpp"
#include "host/to_fixed.hpp"

namespace tp::server {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

ErrorStats compare_images(const Image& d, const Image& r) {
  ErrorStats e;
  const std::size_t n = static_cast<std::size_t>(d.width) * static_cast<std::size_t>(d.height);
  // A reference computed after a resolution change can differ in size from its device frame.
  if (d.width != r.width || d.height != r.height || d.rgb.size() != 3 * n ||
      r.rgb.size() != 3 * n || d.covered.size() != n || r.covered.size() != n)
    return e;
  host::Image8 device(d.width, d.height), reference(r.width, r.height);
  device.rgb = d.rgb;
  reference.rgb = r.rgb;
  const host::Comparison c = host::compare(reference, r.covered, device, d.covered);
  if (c.covered_both == 0) return e;
  e.pixels = static_cast<std::size_t>(c.covered_both);
  e.correctness = c.color_correctness;
  e.mean_levels = c.mean_abs;
  e.max_levels = c.max_abs;
  // PSNR as host::compare takes it, 10·log10(255²/MSE) with the MSE over the three channels;
  // its +inf for identical images is sent as 99 (JSON has no infinity; the page always showed 99).
  e.psnr = std::isinf(c.psnr_db) ? 99.0 : c.psnr_db;
  return e;
}

RenderLoop::RenderLoop(std::unique_ptr<FrameSource> src, Hub& hub, LoopOptions opt)
    : src_(std::move(src)), hub_(hub), opt_(opt) {}

RenderLoop::~RenderLoop() { stop(); }

void RenderLoop::start() {
  {
    std::lock_guard lk(m_);
    running_ = true;
  }
  {
    std::lock_guard lk(rm_);
    ref_running_ = true;
  }
  publish_state();
  thread_ = std::thread([this] { run(); });
  ref_thread_ = std::thread([this] { ref_run(); });
}

void RenderLoop::stop() {
  {
    std::lock_guard lk(m_);
    running_ = false;
  }
  cv_.notify_all();
  {
    std::lock_guard lk(rm_);
    ref_running_ = false;
  }
  rcv_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (ref_thread_.joinable()) ref_thread_.join();
}

Result RenderLoop::submit(Command c, Done done) {
  {
    std::lock_guard lk(m_);
    if (jobs_.size() >= opt_.max_pending_commands)
      return Result::failure("server busy: too many pending commands");
    jobs_.push_back({std::move(c), std::move(done)});
  }
  cv_.notify_all();
  return Result::success();
}

TextPtr RenderLoop::state_message() {
  std::lock_guard lk(m_);
  return state_;
}

void RenderLoop::publish_state() {
  const ViewSettings& s = src_->settings();
  json lights = json::array();
  for (const auto& l : s.lights)
    lights.push_back(
        {{"kind", l.point ? "point" : "directional"}, {"vector", l.vector}, {"color", l.color}});
  json methods = json::array(), method_info = json::array();
  for (const MethodEntry& m : src_->methods()) {
    methods.push_back(m.name);
    method_info.push_back(
        {{"name", m.name}, {"description", m.description}, {"capabilities", m.capabilities}});
  }
  // Without the material's own (a, b), the pair the device derives from n (its closed form, the
  // Kuijk-Blake methods' f): the page shows it, so that choosing (a, b) starts from what renders.
  const fw::cosn::CosnParams derived = fw::cosn::least_squares_params(static_cast<int>(s.n));
  const std::pair<double, double> shown_ab =
      s.use_ab ? std::pair{s.a, s.b}
               : std::pair{host::to_double(derived.a), host::to_double(derived.b)};
  json j = {{"type", "state"},
            {"scene", s.scene},
            {"method", s.method},
            {"budget", s.budget},
            {"use_ab", s.use_ab},
            {"n", s.n},
            {"a", shown_ab.first},
            {"b", shown_ab.second},
            {"ka", s.ka},
            {"kd", s.kd},
            {"ks", s.ks},
            {"color", s.color},
            {"lights", lights},
            {"width", s.width},
            {"height", s.height},
            {"animate", flags_.animate},
            {"paused", flags_.paused},
            {"reference", flags_.reference},
            {"specular_only", s.specular_only},
            {"methods", methods},
            {"method_info", method_info},
            {"scenes", src_->scenes()}};
  auto msg = std::make_shared<const std::string>(json_text(j));
  {
    std::lock_guard lk(m_);
    state_ = msg;
  }
  hub_.set_state(msg);
}

std::optional<RenderLoop::Job> RenderLoop::next_job() {
  std::lock_guard lk(m_);
  if (jobs_.empty()) return std::nullopt;
  Job j = std::move(jobs_.front());
  jobs_.pop_front();
  return j;
}

bool RenderLoop::apply_pending() {
  // A frame period's worth of commands (at least one), the rest after the next frame: each
  // setting re-installs the whole scene in the device (tens of ms for a big mesh), so a storm
  // of 64 queued commands applied at once held every client's frames back for seconds
  // (docs/SERVER.md, "Soak test").
  const auto budget_end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(1.0 / opt_.max_fps));
  bool changed = false;
  for (auto next = next_job(); next; next = Clock::now() < budget_end ? next_job() : std::nullopt) {
    Job& j = *next;
    const bool ref_before = flags_.reference;
    const Result outcome = apply_control(j.cmd, *src_, flags_, step_);
    {
      std::lock_guard lk(m_);  // before the worker can see the job below
      reference_on_ = flags_.reference;
      if (!flags_.reference) error_.reset();
      if (ref_before && !flags_.reference) hub_.forget_reference();  // switched off by this job
    }
    if (outcome.ok()) {
      changed = true;
      if (!changes_loop_flags_only(j.cmd.type)) {
        dirty_ = true;
        abandon_compare("the settings changed");
      }
      if (flags_.reference && !ref_before) offer_reference();
    }
    j.done(outcome);
  }
  if (changed) publish_state();
  if (flags_.compare_requested) {
    flags_.compare_requested = false;
    start_compare();
  }
  return changed;
}

void RenderLoop::start_compare() {
  CompareJob job;
  job.rotation = last_ ? last_->rotation : rotation_;
  for (const MethodEntry& m : src_->methods()) job.methods.push_back(m.name);
  compare_ = std::move(job);
  if (compare_->methods.empty()) return abandon_compare("the source has no methods");
  publish_compare_progress(nullptr);
}

void RenderLoop::abandon_compare(const std::string& why) {
  if (!compare_) return;
  json j = {{"type", "compare_progress"},
            {"done", compare_->rows.size()},
            {"total", compare_->methods.size()},
            {"aborted", why}};
  compare_.reset();
  hub_.broadcast_text(std::make_shared<const std::string>(json_text(j)), false);
}

// One step: the reference first, then one method, with the stream's settings restored after it.
void RenderLoop::compare_step() {
  CompareJob& c = *compare_;
  if (!c.reference) {
    c.reference = src_->reference_task(c.rotation)();
    return;
  }
  const ViewSettings saved = src_->settings();
  ViewSettings s = saved;
  s.method = c.methods[c.rows.size()];
  CompareRow row{s.method, {}, 0, {}};
  if (Result r = src_->apply(s); r.ok()) {
    try {
      for (int k = 0; k < kCompareRenders; ++k) {
        RenderedFrame f = src_->render(c.rotation);
        if (k == 0 || f.render_ms < row.ms) row.ms = f.render_ms;
        if (k == 0) row.error = compare_images(f.image, *c.reference);
      }
    } catch (const std::exception& e) {  // the device refused the frame (render_and_publish)
      row.fault = e.what();
    }
  } else {
    row.fault = r.message();
  }
  if (Result back = src_->apply(saved); !back.ok()) dirty_ = true;
  c.rows.push_back(std::move(row));
  if (c.rows.size() < c.methods.size()) {
    publish_compare_progress(c.rows.back().method.c_str());
    return;
  }
  publish_comparison();
  compare_.reset();
}

void RenderLoop::publish_compare_progress(const char* method) {
  json j = {{"type", "compare_progress"},
            {"done", compare_->rows.size()},
            {"total", compare_->methods.size()}};
  if (method != nullptr) j["method"] = method;
  hub_.broadcast_text(std::make_shared<const std::string>(json_text(j)), true);
}

void RenderLoop::publish_comparison() {
  const CompareJob& c = *compare_;
  double gouraud_ms = 0;
  for (const CompareRow& r : c.rows)
    if (r.method == "gouraud" && r.fault.empty()) gouraud_ms = r.ms;
  json rows = json::array();
  for (const CompareRow& r : c.rows) {
    json row = {{"method", r.method}};
    if (!r.fault.empty()) {
      row["error"] = r.fault;
    } else {
      row.update({{"correctness", r.error.correctness},
                  {"mean_levels", r.error.mean_levels},
                  {"max_levels", r.error.max_levels},
                  {"psnr", r.error.psnr},
                  {"pixels", r.error.pixels},
                  {"ms", r.ms},
                  {"time_ratio", gouraud_ms > 0 ? json(r.ms / gouraud_ms) : json(nullptr)}});
    }
    rows.push_back(std::move(row));
  }
  const ViewSettings& s = src_->settings();
  json j = {{"type", "comparison"},   {"scene", s.scene},       {"width", s.width},
            {"height", s.height},     {"rotation", c.rotation}, {"renders", kCompareRenders},
            {"rows", std::move(rows)}};
  hub_.broadcast_text(std::make_shared<const std::string>(json_text(j)), false);
}

void RenderLoop::render_and_publish(double rotation) {
  RenderedFrame f;
  try {
    f = src_->render(rotation);
  } catch (const std::exception& e) {
    // The device refused this frame: a scene is checked unturned, and a turn can take a vertex
    // out of the device's range. The clients keep the last frame and the stats say why; the
    // loop goes on (the next rotation may fit, and any control message still applies).
    std::lock_guard lk(m_);
    refused_ = e.what();
    return;
  }
  bool was_refused = false;
  {
    std::lock_guard lk(m_);
    was_refused = refused_.has_value();
    refused_.reset();  // before offer_reference below reads it
  }
  const Image& img = f.image;
  const auto sum = fnv1a64(img.rgb);
  bool published = false;
  // Identical consecutive frames (same size and checksum) are not re-sent.
  if (sum != last_checksum_ || img.width != last_w_ || img.height != last_h_) {
    const std::uint32_t id = next_id_++;
    hub_.publish_frame(encode_frame(FrameKind::device, id, img.width, img.height, img.rgb,
                                    f.render_ms, f.counters, sum));
    last_checksum_ = sum;
    last_w_ = img.width;
    last_h_ = img.height;
    last_ = LastFrame{rotation, id, img};
    if (flags_.reference) offer_reference();
    published = true;
  } else if (was_refused && flags_.reference) {
    offer_reference();  // one held back while the frames were refused (offer_reference)
  }
  std::lock_guard lk(m_);
  ++frames_rendered_;
  render_ms_ = f.render_ms;
  counters_ = std::move(f.counters);
  if (published) {
    ++frames_published_;
    frame_id_ = next_id_ - 1;
    frame_checksum_ = sum;
  }
}

void RenderLoop::run() {
  auto last = Clock::now();
  auto window_start = last;
  std::uint64_t window_frames = 0;
  for (;;) {
    {
      std::unique_lock lk(m_);
      if (!running_) return;
    }
    apply_pending();
    const bool animate = flags_.animate && !flags_.paused;
    const bool render = (!flags_.paused && (flags_.animate || dirty_)) || step_;
    const auto now = Clock::now();
    const double dt = std::min(0.1, std::chrono::duration<double>(now - last).count());
    last = now;
    if (!render && compare_) {
      compare_step();
      continue;
    }
    if (!render) {
      std::unique_lock lk(m_);
      cv_.wait_for(lk, std::chrono::milliseconds(100), [&] { return !running_ || !jobs_.empty(); });
      continue;
    }
    if (animate) rotation_ += opt_.radians_per_second * dt;
    if (step_ && !animate) rotation_ += opt_.radians_per_second / 30.0;  // one 30 fps step
    rotation_ = std::fmod(rotation_, 2 * std::numbers::pi);
    step_ = false;
    dirty_ = false;
    const auto t0 = Clock::now();
    render_and_publish(rotation_);
    if (compare_) compare_step();
    ++window_frames;
    const auto t1 = Clock::now();
    {
      std::lock_guard lk(m_);
      loop_ms_ = std::chrono::duration<double, std::milli>(t1 - t0).count();
      const double w = std::chrono::duration<double>(t1 - window_start).count();
      if (w >= 1.0) {
        fps_ = double(window_frames) / w;
        window_frames = 0;
        window_start = t1;
      }
    }
    // Pace to max_fps; wake early for control messages.
    const auto next = t0 + std::chrono::duration_cast<Clock::duration>(
                               std::chrono::duration<double>(1.0 / opt_.max_fps));
    std::unique_lock lk(m_);
    cv_.wait_until(lk, next, [&] { return !running_ || !jobs_.empty(); });
  }
}

void RenderLoop::offer_reference() {
  if (!last_) return;
  {
    // While the device refuses the frames, the frame on screen (last_) may be another scene's
    // (a set_scene the device then refused to draw): a reference of the current scene would be
    // paired with it. The next frame that renders offers one.
    std::lock_guard lk(m_);
    if (refused_) return;
  }
  {
    std::lock_guard lk(rm_);
    // Latest only: an unstarted older job is replaced. The task snapshots the scene here, on
    // the render-loop thread, so the worker never touches the live source.
    ref_job_ = RefJob{src_->reference_task(last_->rotation), last_->frame_id, last_->device};
  }
  rcv_.notify_all();
}

void RenderLoop::ref_run() {
  for (;;) {
    RefJob job;
    {
      std::unique_lock lk(rm_);
      rcv_.wait(lk, [&] { return !ref_running_ || ref_job_.has_value(); });
      if (!ref_running_) return;
      job = std::move(*ref_job_);
      ref_job_.reset();
    }
    Image ref = job.task();
    ErrorStats e = compare_images(job.device, ref);
    e.frame_id = job.frame_id;
    FramePtr frame =
        encode_frame(FrameKind::reference, job.frame_id, ref.width, ref.height, ref.rgb, 0);
    std::lock_guard lk(m_);        // held while publishing: switching off cannot come in between
    if (!reference_on_) continue;  // switched off meanwhile
    error_ = e;
    hub_.publish_frame(std::move(frame));
  }
}

std::string RenderLoop::stats_message(std::size_t clients) {
  std::lock_guard lk(m_);
  json counters = json::object();
  for (const auto& [k, v] : counters_) counters[k] = v;
  json j = {{"type", "stats"},
            {"fps", fps_},
            {"render_ms", render_ms_},
            {"loop_ms", loop_ms_},
            {"frames_rendered", frames_rendered_},
            {"frames_published", frames_published_},
            {"frame", {{"id", frame_id_}, {"checksum", hex64(frame_checksum_)}}},
            {"clients", clients},
            {"counters", counters}};
  if (refused_) j["refused"] = *refused_;
  if (error_)
    j["error"] = {{"frame_id", error_->frame_id},       {"pixels", error_->pixels},
                  {"correctness", error_->correctness}, {"mean_levels", error_->mean_levels},
                  {"max_levels", error_->max_levels},   {"psnr", error_->psnr}};
  return json_text(j);
}

}  // namespace tp::server
