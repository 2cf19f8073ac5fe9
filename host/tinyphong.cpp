// tinyphong: the command-line tool. Renders scenes with the emulated device, renders the double
// reference, and compares images (Vlasic's measures, docs/RESULTS.md).
//
//   tinyphong render scenes/teapot.json --method gouraud -o teapot.png
//   tinyphong reference scenes/teapot.json -o ref.png [--exr ref.exr] [--angular]
//   tinyphong compare ref.png teapot.png [--diff diff.png] [--row 240]
//   tinyphong methods
//   tinyphong record scenes/teapot.json --method kb -o teapot.tpcmd [--size WxH]
//   tinyphong record scenes/*.json --method kb --dir streams/ [--size WxH]
//   tinyphong replay teapot.tpcmd [-o out.png] [--hash]   (several files with --hash)
//   tinyphong memory [--vertices N] [--indices N]
//   tinyphong stress [--quick] [--methods m1,m2] [--cases NAME] [--seed S] [--json FILE]
//                    [--images DIR]
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "firmware/registry.hpp"
#include "firmware/types.hpp"
#include "host/cli_options.hpp"
#include "host/command_stream.hpp"
#include "host/device_renderer.hpp"
#include "host/file_identity.hpp"
#include "host/image_io.hpp"
#include "host/metrics.hpp"
#include "host/reference.hpp"
#include "host/scene.hpp"
#include "host/size_text.hpp"
#include "host/standard_output.hpp"
#include "host/stress_command.hpp"

namespace {

using namespace tp::host;

struct SceneOptions {
  std::string scene;
  std::string method;
  int budget = 0;    // 0: the scene's
  std::string size;  // "WxH"
  double rotate_deg = 0;
  bool specular_only = false;
  bool no_depth_buffer = false;
  bool small_part = false;  // record only
};

// --budget, for the commands that run the device (render, record).
void add_budget_option(CLI::App* cmd, SceneOptions& o) {
  const int most = static_cast<int>(tp::fw::kMaxBudgetLevels);
  cmd->add_option("--budget", o.budget,
                  "error budget in output levels for kb-adaptive, 1.." + std::to_string(most) +
                      " (default: the scene's, else 1)")
      ->transform(whole_number(1, most));
}

// --no-depth-buffer, for the commands that run the device (render, record).
void add_depth_buffer_option(CLI::App* cmd, SceneOptions& o) {
  cmd->add_flag("--no-depth-buffer", o.no_depth_buffer,
                "lay out no depth buffer (4 bytes per pixel less; the depth test passes every "
                "pixel: enough for a closed convex mesh, docs/TARGET.md)");
}

// A number written in decimal: "30", "-12.5", "+45", "1e3". CLI11's own reading also took
// hexadecimal ("0x10", "0x1p4") and a leading space (" 16"), text --seed refuses (found by
// review, 2026-12-07).
std::optional<double> decimal(std::string_view text) {
  const bool plus = text.starts_with('+');
  if (plus) text.remove_prefix(1);
  if (text.empty() || (plus && text.front() == '-')) return std::nullopt;
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

// An angle in degrees: decimal, finite, and small enough that its radians keep their precision.
const CLI::Validator kAngle(
    [](std::string& text) -> std::string {
      const std::optional<double> v = decimal(text);
      if (!v || !std::isfinite(*v) || std::abs(*v) > 1e6)
        return "an angle in degrees, finite and within ±1e6, got '" + text + "'";
      return "";
    },
    "DEGREES");

void add_scene_options(CLI::App* cmd, SceneOptions& o) {
  cmd->add_option("scene", o.scene, "scene file (JSON), e.g. scenes/teapot.json")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--size", o.size, "override the resolution, WIDTHxHEIGHT (e.g. 1024x1024)")
      ->check(size_check());
  cmd->add_option("--rotate", o.rotate_deg, "rotate the objects about the world y axis (degrees)")
      ->check(kAngle);
  cmd->add_flag("--specular-only", o.specular_only,
                "the specular part alone: ka = kd = 0 (Vlasic's specular-only images)");
}

// --budget given for a method whose image does not depend on it (the registry's reads_budget):
// the frame is drawn as without it, and the user is told, not refused, so that a script may pass
// one budget to every method it measures (docs/DECISIONS.md, "A budget no method reads").
void note_unread_budget(const SceneOptions& o, const Scene& s) {
  if (o.budget == 0) return;
  const tp::fw::MethodInfo* row = tp::fw::find_method(s.method);
  if (row == nullptr || row->reads_budget) return;
  std::string readers;
  for (const tp::fw::MethodInfo& m : tp::fw::kMethodTable)
    if (m.reads_budget) readers += (readers.empty() ? "" : ", ") + std::string(m.name);
  std::cerr << "tinyphong: note: --budget " << o.budget << " has no effect on " << s.file
            << ": its method " << s.method << " reads no error budget (" << readers << " do)\n";
}

Scene load(const SceneOptions& o) {
  Scene s = load_scene(o.scene);
  if (!o.method.empty()) s.method = o.method;
  note_unread_budget(o, s);
  if (o.budget != 0) s.budget = o.budget;
  if (o.specular_only) keep_specular_only(s);
  if (o.no_depth_buffer || o.small_part) s.depth_buffer = false;
  if (o.small_part) s.small_part_frame = true;
  if (!o.size.empty()) {
    const Size size = parse_size(o.size).value();  // checked as the option was read (size_check)
    s.width = size.width;
    s.height = size.height;
  }
  return s;
}

// What a scene's refusal of an output names: the scene file and the meshes it names.
std::vector<Input> inputs_of(const Scene& scene) {
  std::vector<Input> inputs{{scene.file, "the scene file " + scene.file}};
  for (const MeshSpec& m : scene.meshes)
    if (!m.obj.empty())
      inputs.push_back({m.obj, "the mesh " + m.obj.string() + " of " + scene.file});
  return inputs;
}

// The device's buffers sized for the scene's meshes: DeviceRenderer's defaults hold 2^17
// vertices, a scene may have up to kMaxSceneVertices (host/scene.hpp).
struct Capacity {
  std::uint32_t vertices = 0, indices = 0;
};
Capacity capacity_for(const Scene& s) {
  std::size_t vertices = 0, triangles = 0;
  for (const auto& m : s.meshes) {
    vertices += m.mesh.positions.size();
    triangles += m.mesh.triangles.size();
  }
  return {static_cast<std::uint32_t>(vertices), static_cast<std::uint32_t>(3 * triangles)};
}

double radians(double deg) { return deg * 3.14159265358979323846 / 180.0; }

void print_counters(const CounterSnapshot& counters) {
  for (const auto& [name, value] : counters) std::cout << "  " << name << " = " << value << "\n";
}

void print_comparison(const Comparison& c) {
  std::cout << "pixels compared:      " << c.covered_both << "\n"
            << "only in first:        " << c.only_reference << "\n"
            << "only in second:       " << c.only_evaluated << "\n";
  if (!c.measured()) {  // printed a perfect score: correctness 1, PSNR inf, errors 0
    std::cout << "no pixel is covered in both images: no error to measure\n";
    return;
  }
  std::cout << "colour correctness:   " << c.color_correctness << "  (Vlasic eq. 6.1)\n"
            << "PSNR:                 " << c.psnr_db << " dB\n"
            << "mean |error|:         " << c.mean_abs << " levels\n"
            << "max |error|:          " << c.max_abs << " levels\n";
}

int run_render(const SceneOptions& o, const std::string& out, bool compare_ref) {
  const Scene scene = load(o);
  if (writes_over_input("render", {out}, inputs_of(scene))) return 2;
  const Capacity cap = capacity_for(scene);
  DeviceRenderer device(scene.width, scene.height, cap.vertices, cap.indices);
  device.set_scene(scene);
  const DeviceFrame frame = device.render(radians(o.rotate_deg));
  write_png(out, frame.image());
  std::cout << "rendered " << scene.name << " (" << frame.width << "x" << frame.height << ", "
            << scene.method << ") in " << frame.render_ms << " ms -> " << out << "\n"
            << "counters:\n";
  print_counters(frame.counters);
  if (compare_ref) {
    const ReferenceFrame ref = device.render_reference(radians(o.rotate_deg));
    std::cout << "against the double Phong reference:\n";
    print_comparison(compare(ref.image(), ref.covered, frame.image(), frame.covered));
  }
  return 0;
}

int run_reference(const SceneOptions& o, const std::string& out, const std::string& exr,
                  bool angular) {
  const Scene scene = load(o);
  if (writes_over_input("reference", {out, exr}, inputs_of(scene))) return 2;
  if (!exr.empty() && same_output(exr, out)) {
    std::cerr << "tinyphong reference: --exr " << exr << " is -o " << out
              << ", the image it would replace: nothing written\n";
    return 2;
  }
  const Capacity cap = capacity_for(scene);
  DeviceRenderer device(scene.width, scene.height, cap.vertices, cap.indices);
  device.set_scene(scene);  // the same checks as a device render: one definition of "valid",
  device.render(radians(o.rotate_deg));  // the frame's included (a turn can leave the range)
  const Interpolation interp = angular ? Interpolation::Angular : Interpolation::Phong;
  const ReferenceFrame ref = device.render_reference(radians(o.rotate_deg), interp);
  write_png(out, ref.image());
  std::cout << "reference (" << (angular ? "angular" : "phong") << ") " << ref.width << "x"
            << ref.height << " -> " << out << "\n";
  if (!exr.empty()) {
    write_exr(exr, ref.linear);
    std::cout << "linear float image -> " << exr << "\n";
  }
  return 0;
}

// The n pixels with the largest channel difference, covered in both images.
void print_worst(const Image8& a, const Mask& ma, const Image8& b, const Mask& mb, int n) {
  struct Px {
    int d, x, y;
  };
  std::vector<Px> px;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(a.width) +
                            static_cast<std::size_t>(x);
      if (!ma[i] || !mb[i]) continue;
      int d = 0;
      for (int c = 0; c < 3; ++c)
        d = std::max(d, std::abs(int{a.at(x, y)[c]} - int{b.at(x, y)[c]}));
      if (d > 0) px.push_back({d, x, y});
    }
  const auto count = std::min<std::size_t>(px.size(), static_cast<std::size_t>(n));
  // Ties in row order, then column: the list for N is the start of the list for any larger N.
  std::partial_sort(px.begin(), px.begin() + static_cast<std::ptrdiff_t>(count), px.end(),
                    [](const Px& l, const Px& r) {
                      return l.d != r.d ? l.d > r.d : l.y != r.y ? l.y < r.y : l.x < r.x;
                    });
  std::cout << "worst pixels (x, y: first rgb / second rgb):\n";
  for (std::size_t k = 0; k < count; ++k) {
    const auto* pa = a.at(px[k].x, px[k].y);
    const auto* pb = b.at(px[k].x, px[k].y);
    std::cout << "  " << px[k].x << ", " << px[k].y << ": " << int{pa[0]} << " " << int{pa[1]}
              << " " << int{pa[2]} << " / " << int{pb[0]} << " " << int{pb[1]} << " " << int{pb[2]}
              << "\n";
  }
}

// compare's options beyond its two images.
struct CompareCli {
  std::string diff;
  std::optional<int> row;
  int worst = 0;
  std::string background = "0,0,0";  // checked by kBackground
};

// R,G,B in 8-bit levels, each a whole decimal number in 0..255: the colour compare takes for
// "not covered" in the files it reads.
std::optional<glm::u8vec3> parse_background(const std::string& text) {
  glm::u8vec3 colour;
  std::size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t comma = k < 2 ? text.find(',', start) : text.size();
    if (comma == std::string::npos) return std::nullopt;
    std::string part = text.substr(start, comma - start);  // "3,4" for a fourth: refused
    if (!whole_number(0, 255)(part).empty()) return std::nullopt;
    colour[k] = static_cast<std::uint8_t>(std::stoi(part));
    start = comma + 1;
  }
  return colour;
}

const CLI::Validator kBackground(
    [](std::string& text) -> std::string {
      return parse_background(text) ? ""
                                    : "R,G,B: three whole numbers in 0..255, got '" + text + "'";
    },
    "R,G,B");

int run_compare(const std::string& a, const std::string& b, const CompareCli& o) {
  const std::string& diff = o.diff;
  const std::optional<int> row = o.row;
  if (writes_over_input("compare", {diff},
                        {{a, "the first image " + a}, {b, "the second image " + b}}))
    return 2;
  const Image8 ia = read_png(a), ib = read_png(b);
  if (ia.width != ib.width || ia.height != ib.height) {
    std::cerr << "tinyphong compare: " << a << " is " << ia.width << "x" << ia.height << " but "
              << b << " is " << ib.width << "x" << ib.height << "\n";
    return 2;
  }
  if (row && (*row < 0 || *row >= ia.height)) {  // before anything is printed or written
    std::cerr << "tinyphong compare: --row " << *row << " outside 0.." << ia.height - 1 << "\n";
    return 2;
  }
  // The files carry no coverage: a pixel of exactly the background colour is taken as not
  // covered (render --compare uses the device's and the reference's own coverage).
  const glm::u8vec3 background = *parse_background(o.background);
  const Mask ma = mask_from_background(ia, background), mb = mask_from_background(ib, background);
  const auto whole = [](const Mask& m) { return std::ranges::all_of(m, [](auto c) { return c; }); };
  if (whole(ma) && whole(mb))  // most likely a scene's background that is not the one given
    std::cerr << "tinyphong compare: note: no pixel of either image is the background colour "
              << o.background << ", so every pixel counts as covered (--background R,G,B gives "
              << "the scene's)\n";
  print_comparison(compare(ia, ma, ib, mb));
  if (o.worst > 0) print_worst(ia, ma, ib, mb, o.worst);
  if (!diff.empty()) {
    write_png(diff, difference_image(ia, ma, ib, mb));
    std::cout << "difference image (Vlasic eq. 6.2) -> " << diff << "\n";
  }
  if (row) {
    const auto ca = scanline_curve(ia, ma, *row), cb = scanline_curve(ib, mb, *row);
    std::cout << "x,first,second  (Vlasic eq. 6.3, row " << *row << ")\n";
    for (std::size_t x = 0; x < ca.size(); ++x) {
      if (!ca[x] && !cb[x]) continue;
      std::cout << x << "," << (ca[x] ? std::to_string(*ca[x]) : "") << ","
                << (cb[x] ? std::to_string(*cb[x]) : "") << "\n";
    }
  }
  return 0;
}

// The command words the driver sends for one frame of the scene (the device's checks of the
// scene and of the frame, as a render's, throw here: no stream that replay would refuse).
std::vector<std::uint32_t> record_words(const Scene& scene, double rotate_deg) {
  const Capacity cap = capacity_for(scene);
  DeviceRenderer device(scene.width, scene.height, cap.vertices, cap.indices);
  device.set_scene(scene);
  device.render(radians(rotate_deg));
  return device.record(radians(rotate_deg));
}

struct RecordCli {
  SceneOptions options;  // options.scene unused: the scenes are below
  std::vector<std::string> scenes;
  std::string out, dir;
};

// One scene to -o FILE, or several (one process: the build records 240 streams) into --dir
// as DIR/<scene file's stem>.tpcmd. Every scene is read, every output checked and every
// stream recorded before any is written: a bad scene (one that does not parse, or one the
// device's checks refuse), two scenes of one output, or an output that is one of the inputs,
// writes nothing.
int run_record(const RecordCli& cli) {
  if (cli.out.empty() == cli.dir.empty() || (!cli.out.empty() && cli.scenes.size() != 1)) {
    std::cerr << "tinyphong record: give either -o FILE (one scene) or --dir DIR\n";
    return 2;
  }
  std::vector<Scene> scenes;
  for (const std::string& file : cli.scenes) {
    SceneOptions o = cli.options;
    o.scene = file;
    scenes.push_back(load(o));
  }
  std::vector<std::string> outs;
  for (const std::string& scene : cli.scenes) {
    outs.push_back(cli.out.empty() ? (std::filesystem::path(cli.dir) /
                                      (std::filesystem::path(scene).stem().string() + ".tpcmd"))
                                         .string()
                                   : cli.out);
    // Two scenes of one name in different folders would write one file.
    const auto same = std::find_if(outs.begin(), outs.end() - 1, [&](const std::string& o) {
      return same_output(o, outs.back());
    });
    if (same != outs.end() - 1) {
      std::cerr << "tinyphong record: " << cli.scenes[static_cast<std::size_t>(same - outs.begin())]
                << " and " << scene << " would both be recorded to " << outs.back() << "\n";
      return 2;
    }
  }
  std::vector<Input> inputs;
  for (const Scene& scene : scenes) std::ranges::copy(inputs_of(scene), std::back_inserter(inputs));
  if (writes_over_input("record", outs, inputs)) return 2;
  std::vector<std::vector<std::uint32_t>> streams;
  for (const Scene& scene : scenes) streams.push_back(record_words(scene, cli.options.rotate_deg));
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    write_command_file(outs[i], streams[i]);
    const Scene& scene = scenes[i];
    std::cout << "recorded " << scene.name << " (" << scene.width << "x" << scene.height << ", "
              << scene.method << "): " << streams[i].size() << " words -> " << outs[i] << "\n";
  }
  return 0;
}

// Runs a .tpcmd file through a fresh device; the PNG and/or the framebuffer hash, printed as
// "HASH  FILE" (as sha256sum does), so that a test hashes many streams in one run.
int run_replay_one(const std::string& in, const std::string& out, bool print_hash) {
  const std::vector<std::uint32_t> words = read_command_file(in);
  std::optional<StreamReplay> replay;
  try {
    replay.emplace(words);
  } catch (const std::runtime_error& e) {  // a StreamError, the block's limit, no viewport
    std::cerr << "tinyphong replay: " << in << ": " << e.what() << "\n";
    return 1;
  }
  if (const std::optional<std::string> why = unfinished_frame(words)) {
    std::cerr << "tinyphong replay: " << in << ": " << *why << "\n";
    return 1;
  }
  const tp::fw::Device& device = replay->device();
  if (print_hash)
    std::cout << hash_hex(framebuffer_hash(device.framebuffer())) << "  " << in << "\n";
  if (!out.empty()) {
    write_png(out, read_frame(device).image());
    if (!print_hash) std::cout << "replayed " << words.size() << " words -> " << out << "\n";
  }
  return 0;
}

int run_replay(const std::vector<std::string>& in, const std::string& out, bool print_hash) {
  if (out.empty() && !print_hash) {
    std::cerr << "tinyphong replay: nothing to do: give -o FILE.png and/or --hash\n";
    return 2;
  }
  if (in.size() > 1 && !out.empty()) {
    std::cerr << "tinyphong replay: -o takes one stream, " << in.size() << " given\n";
    return 2;
  }
  if (!in.empty() && writes_over_input("replay", {out}, {{in.front(), "the stream " + in.front()}}))
    return 2;
  int status = 0;
  for (const std::string& file : in) {
    try {
      status = std::max(status, run_replay_one(file, out, print_hash));
    } catch (const std::runtime_error& e) {  // an unreadable file: report it, go on
      std::cerr << "tinyphong replay: " << e.what() << "\n";
      status = 1;
    }
  }
  return status;
}

// The device's memory block per resolution, pixel format and method (Device::memory_required):
// what a port to a part with fixed RAM needs to know (docs/TARGET.md, "Memory").
int run_memory(std::uint32_t vertices, std::uint32_t indices) {
  using tp::fw::Method;
  const struct { std::uint32_t w, h; } sizes[] = {{160, 120}, {320, 240}, {640, 480}};
  const struct {
    tp::fw::PixelFormat format;
    const char* name;
  } formats[] = {{tp::fw::PixelFormat::kRgb565, "RGB565"},
                 {tp::fw::PixelFormat::kRgb888, "RGB888"}};
  // One column per registered method, except where a method's state has the same size as an
  // earlier one's (the -noskip and -exact variants share their method's): named below the table.
  const tp::fw::BufferCapacityCmd cap{vertices, indices};
  std::vector<Method> columns;
  std::string shared;
  for (const auto& row : method_names()) {
    const auto same = std::find_if(columns.begin(), columns.end(), [&](Method m) {
      return tp::fw::Device::method_bytes(m) == row.slot.bytes &&
             tp::fw::find_method(m)->slot.traits.lights_vertices == row.slot.traits.lights_vertices;
    });
    if (same == columns.end())
      columns.push_back(row.id);
    else
      shared += std::string(shared.empty() ? "" : ", ") + std::string(row.name) + " as " +
                std::string(method_name(*same));
  }
  std::cout << "Device memory block in bytes (Device::memory_required), " << vertices
            << " vertices and " << indices << " indices, no write counts\n\n";
  std::cout << "| resolution | format | depth buffer |";
  for (const Method m : columns) std::cout << " " << method_name(m) << " |";
  std::cout << "\n|---|---|---|";
  for (std::size_t i = 0; i < columns.size(); ++i) std::cout << "---:|";
  std::cout << "\n";
  for (const auto& size : sizes)
    for (const auto& format : formats)
      for (const bool depth : {true, false}) {
        const tp::fw::ViewportCmd vp{size.w, size.h, format.format, false, depth};
        std::cout << "| " << size.w << "x" << size.h << " | " << format.name << " | "
                  << (depth ? "yes" : "no") << " |";
        for (const Method m : columns)
          std::cout << " " << tp::fw::Device::memory_required(vp, cap, m) << " |";
        std::cout << "\n";
      }
  std::cout << "\nsizeof(Device) = " << sizeof(tp::fw::Device)
            << " bytes, outside the block; method state in the block:";
  for (const Method m : columns)
    std::cout << " " << method_name(m) << " " << tp::fw::Device::method_bytes(m) << ";";
  if (!shared.empty()) std::cout << " the same bytes: " << shared << ".";
  std::cout << "\n";
  return 0;
}

int run(int argc, char** argv);

// While a command writes one of its files to standard output (`record -o /dev/stdout | replay
// /dev/stdin`), its report goes to standard error: the lines "recorded ... -> /dev/stdout" were
// written into the stream (found by review, 2026-12-08).
class ReportAwayFromFiles {
 public:
  explicit ReportAwayFromFiles(const std::vector<std::string>& outputs) {
    if (std::ranges::any_of(outputs, [](const std::string& o) { return is_standard_output(o); }))
      saved_ = std::cout.rdbuf(std::cerr.rdbuf());
  }
  ~ReportAwayFromFiles() {
    if (saved_ != nullptr) std::cout.rdbuf(saved_);
  }
  ReportAwayFromFiles(const ReportAwayFromFiles&) = delete;
  ReportAwayFromFiles& operator=(const ReportAwayFromFiles&) = delete;

 private:
  std::streambuf* saved_ = nullptr;
};

}  // namespace

// A failed write to standard output is an error: exit 1, or 3 for stress, whose 1 means a
// result outside its bound (docs/STABILITY.md).
int main(int argc, char** argv) {
  const int status = run(argc, argv);
  if (standard_output_written("tinyphong")) return status;
  const bool stress = argc > 1 && std::string_view(argv[1]) == "stress";
  return status != 0 && status != 1 ? status : stress ? 3 : 1;
}

namespace {

int run(int argc, char** argv) {
  CLI::App app{"tinyphong: an emulated integer-only GPU and its desktop tools"};
  app.require_subcommand(1);

  SceneOptions render_opts;
  std::string render_out = "out.png";
  bool render_compare = false;
  auto* render = app.add_subcommand("render", "render a scene with the emulated device");
  add_scene_options(render, render_opts);
  render->add_option("--method,-m", render_opts.method, "shading method (see `tinyphong methods`)")
      ->check(method_check());
  add_budget_option(render, render_opts);
  add_depth_buffer_option(render, render_opts);
  render->add_option("-o,--output", render_out, "PNG file to write (replaced if it exists)")
      ->capture_default_str();
  render->add_flag("--compare", render_compare,
                   "also render the double reference and print the error metrics");

  SceneOptions ref_opts;
  std::string ref_out = "reference.png", ref_exr;
  bool ref_angular = false;
  auto* reference = app.add_subcommand("reference", "render the double-precision reference");
  add_scene_options(reference, ref_opts);
  reference->add_option("-o,--output", ref_out, "PNG file to write, 8-bit (replaced if it exists)")
      ->capture_default_str();
  reference->add_option("--exr", ref_exr, "also write the linear float image as OpenEXR");
  reference->add_flag("--angular", ref_angular,
                      "slerp the normals (Kuijk-Blake's interpolation) instead of Phong's");

  std::string cmp_a, cmp_b;
  CompareCli cmp_opts;
  auto* cmp =
      app.add_subcommand("compare", "error metrics of SECOND against FIRST (the reference)");
  cmp->add_option("first", cmp_a, "reference image")->required()->check(CLI::ExistingFile);
  cmp->add_option("second", cmp_b, "evaluated image")->required()->check(CLI::ExistingFile);
  cmp->add_option("--diff", cmp_opts.diff, "write the gamma-enhanced difference image (eq. 6.2)");
  cmp->add_option("--row", cmp_opts.row,
                  "print the illumination curve of this row (eq. 6.3) as CSV")
      ->transform(whole_number(0, std::numeric_limits<int>::max()));

  cmp->add_option("--worst", cmp_opts.worst, "list the N pixels that differ most")
      ->transform(whole_number(0, std::numeric_limits<int>::max()));
  cmp->add_option("--background", cmp_opts.background,
                  "the scenes' background colour in 8-bit levels: a pixel of exactly this colour "
                  "is taken as not covered, in either image (render --compare knows the coverage "
                  "exactly)")
      ->check(kBackground)
      ->capture_default_str();

  auto* methods = app.add_subcommand("methods", "list the shading methods");

  RecordCli rec;
  auto* record = app.add_subcommand(
      "record", "write the device command words of one frame of a scene (.tpcmd, docs/TARGET.md)");
  record->add_option("scenes", rec.scenes, "scene file(s) (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  record->add_option("--size", rec.options.size, "override the resolution, WIDTHxHEIGHT")
      ->check(size_check());
  record
      ->add_option("--rotate", rec.options.rotate_deg,
                   "rotate the objects about the world y axis (degrees)")
      ->check(kAngle);
  record->add_option("--method,-m", rec.options.method, "shading method (see `tinyphong methods`)")
      ->check(method_check());
  add_budget_option(record, rec.options);
  add_depth_buffer_option(record, rec.options);
  record->add_flag("--small-part", rec.options.small_part,
                   "the frame a part with little RAM draws: RGB565, no depth buffer, no write "
                   "counts (docs/TARGET.md, \"A small part\")");
  record->add_option("-o,--output", rec.out, ".tpcmd file to write (one scene)");
  record->add_option("--dir", rec.dir, "write DIR/<scene>.tpcmd for each scene")
      ->check(CLI::ExistingDirectory);

  std::vector<std::string> rep_in;
  std::string rep_out;
  bool rep_hash = false;
  auto* replay =
      app.add_subcommand("replay", "run a .tpcmd command stream through the device (host)");
  replay->add_option("streams", rep_in, ".tpcmd file(s)")->required()->check(CLI::ExistingFile);
  replay->add_option("-o,--output", rep_out, "PNG file to write");
  replay->add_flag("--hash", rep_hash,
                   "print the FNV-1a 64 hash of the framebuffer (what the Cortex-M images print)");

  std::uint32_t mem_vertices = 0, mem_indices = 0;
  auto* memory = app.add_subcommand(
      "memory", "the device's memory block per resolution, pixel format and method (bytes)");
  memory->add_option("--vertices", mem_vertices, "vertex buffer capacity")
      ->transform(whole_number(0, tp::fw::kMaxVertexCapacity));
  memory->add_option("--indices", mem_indices, "index buffer capacity")
      ->transform(whole_number(0, tp::fw::kMaxIndexCapacity));

  StressCli stress_cli;
  add_stress_command(app, stress_cli);

  if (const std::optional<int> status = parse_options(app, argc, argv)) return *status;
  // The files the chosen command writes (not the other commands' defaults: `methods > out.png`
  // would have sent the list to standard error).
  const std::vector<std::string> outputs =
      *render      ? std::vector<std::string>{render_out}
      : *reference ? std::vector<std::string>{ref_out, ref_exr}
      : *cmp       ? std::vector<std::string>{cmp_opts.diff}
      : *record    ? std::vector<std::string>{rec.out}
      : *replay    ? std::vector<std::string>{rep_out}
      : app.got_subcommand("stress")
          ? std::vector<std::string>{stress_cli.json, stress_cli.bounds_out}
          : std::vector<std::string>{};
  const ReportAwayFromFiles report(outputs);
  try {
    if (*render) return run_render(render_opts, render_out, render_compare);
    if (*reference) return run_reference(ref_opts, ref_out, ref_exr, ref_angular);
    if (*cmp) return run_compare(cmp_a, cmp_b, cmp_opts);
    if (app.got_subcommand("stress")) return run_stress_command(stress_cli);
    if (*record) return run_record(rec);
    if (*replay) return run_replay(rep_in, rep_out, rep_hash);
    if (*memory) return run_memory(mem_vertices, mem_indices);
    if (*methods) {
      for (const auto& m : method_names())
        std::cout << m.name << "\t" << m.description << "\t" << capabilities_text(m.caps) << "\n";
      return 0;
    }
  } catch (const SceneError& e) {
    std::cerr << "tinyphong: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "tinyphong: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace
