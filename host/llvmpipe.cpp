// Mesa llvmpipe through OSMesa: an OpenGL 3.3 core context rendering into our own buffer.
#include "host/llvmpipe.hpp"

#include <chrono>
#include <cstdlib>

#define GL_GLEXT_PROTOTYPES 1  // libOSMesa exports the whole GL API; no loader is needed
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "firmware/types.hpp"

namespace tp::host {

namespace {

// The double reference's Blinn-Phong (host/reference.cpp, blinn_phong) in float: the same
// vectors, the same clamps, no N·L gate on the specular term; V = (0, 0, 1) for an eye at
// infinity. Every light in one loop, as a user's shader would have it.
constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 model_view;
uniform mat3 normal_matrix;  // model_view's upper 3x3 (uniform scale only, as in the scenes)
uniform mat4 projection;
out vec3 eye_position;
out vec3 eye_normal;
void main() {
  vec4 p = model_view * vec4(position, 1.0);
  eye_position = p.xyz;
  eye_normal = normalize(normal_matrix * normal);  // unit at the vertices, as in the reference
  gl_Position = projection * p;
}
)";

// LIGHTS, the scene's light count, is defined in front of it (set_scene compiles it per scene),
// so that the loop's bound is a constant the compiler can unroll, as a shader written for the
// scene would have it.
constexpr const char* kFragmentShader = R"(
in vec3 eye_position;
in vec3 eye_normal;
uniform int light_is_point[LIGHTS > 0 ? LIGHTS : 1];
uniform vec3 light_vector[LIGHTS > 0 ? LIGHTS : 1];  // eye space: unit direction, or position
uniform vec3 light_colour[LIGHTS > 0 ? LIGHTS : 1];
uniform vec3 colour;
uniform float ka, kd, ks, n;
uniform bool eye_at_infinity;
out vec4 fragment;
void main() {
  vec3 N = normalize(eye_normal);
  vec3 V = eye_at_infinity ? vec3(0.0, 0.0, 1.0) : normalize(-eye_position);
  vec3 c = ka * colour;
  for (int i = 0; i < LIGHTS; ++i) {
    vec3 L = light_is_point[i] != 0 ? normalize(light_vector[i] - eye_position) : light_vector[i];
    vec3 LV = L + V;
    float nl = max(0.0, dot(N, L));
    float nh = dot(LV, LV) > 0.0 ? max(0.0, dot(N, normalize(LV))) : 0.0;
    float specular = nh > 0.0 ? pow(nh, n) : 0.0;
    c += light_colour[i] * (kd * nl * colour + vec3(ks * specular));
  }
  fragment = vec4(clamp(c, 0.0, 1.0), 1.0);  // alpha 1: covered (the clear leaves 0)
}
)";

glm::dmat4 rotation_about_y(double radians) {
  return glm::rotate(glm::dmat4(1.0), radians, glm::dvec3(0, 1, 0));
}

}  // namespace

struct LlvmpipePeer::Gl {
  struct MeshBuffers {
    GLuint vao = 0, vertices = 0, indices = 0;
    GLsizei index_count = 0;
    glm::dmat4 model{1.0};
  };
  int width = 0, height = 0;
  OSMesaContext context = nullptr;
  std::vector<std::uint8_t> buffer;  // RGBA8, the context's colour buffer
  GLuint program = 0;
  std::vector<MeshBuffers> meshes;
  Scene scene;
  bool loaded = false;

  GLint uniform(const char* name) const { return glGetUniformLocation(program, name); }
  void release_meshes();
};

namespace {

GLuint compile(GLenum kind, const char* source) {
  const GLuint s = glCreateShader(kind);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = GL_FALSE;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[2048] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw PeerError(std::string("llvmpipe: shader does not compile: ") + log);
  }
  return s;
}

GLuint link_program(std::size_t lights) {
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const std::string fragment =
      "#version 330 core\n#define LIGHTS " + std::to_string(lights) + "\n" + kFragmentShader;
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment.c_str());
  const GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[2048] = {};
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw PeerError(std::string("llvmpipe: program does not link: ") + log);
  }
  return p;
}

void check_gl(const char* what) {
  if (const GLenum e = glGetError(); e != GL_NO_ERROR)
    throw PeerError(std::string("llvmpipe: GL error ") + std::to_string(e) + " in " + what);
}

}  // namespace

void LlvmpipePeer::Gl::release_meshes() {
  for (MeshBuffers& m : meshes) {
    glDeleteBuffers(1, &m.vertices);
    glDeleteBuffers(1, &m.indices);
    glDeleteVertexArrays(1, &m.vao);
  }
  meshes.clear();
}

Image8 PeerFrame::image() const {
  Image8 img(width, height);
  img.rgb = rgb;
  return img;
}

LlvmpipePeer::LlvmpipePeer(int width, int height) : gl_(std::make_unique<Gl>()) {
  if (width < 1 || height < 1 || width > static_cast<int>(fw::kMaxDimension) ||
      height > static_cast<int>(fw::kMaxDimension))
    throw PeerError("llvmpipe: size " + std::to_string(width) + "x" + std::to_string(height) +
                    " outside 1.." + std::to_string(fw::kMaxDimension));
  // One thread, like the device; llvmpipe reads these when its first screen is created.
  setenv("LP_NUM_THREADS", "0", 1);
  setenv("GALLIUM_DRIVER", "llvmpipe", 1);
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_STENCIL_BITS,
                         0,
                         OSMESA_ACCUM_BITS,
                         0,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         3,
                         0};
  Gl& g = *gl_;
  g.width = width;
  g.height = height;
  g.context = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!g.context) throw PeerError("llvmpipe: OSMesa refused an OpenGL 3.3 core context");
  g.buffer.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 0);
  if (!OSMesaMakeCurrent(g.context, g.buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
    OSMesaDestroyContext(g.context);
    throw PeerError("llvmpipe: OSMesaMakeCurrent failed");
  }
  OSMesaPixelStore(OSMESA_Y_UP, 0);  // row 0 at the top, as our images
  if (renderer().find("llvmpipe") == std::string::npos) {
    const std::string r = renderer();
    OSMesaDestroyContext(g.context);
    throw PeerError("llvmpipe: the OSMesa renderer is '" + r + "', not llvmpipe");
  }
  glViewport(0, 0, width, height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);  // strictly nearer, as the device (docs/CONVENTIONS.md, "Depth")
  glFrontFace(GL_CCW);   // front faces counter-clockwise in NDC, as the device
  glCullFace(GL_BACK);
}

LlvmpipePeer::~LlvmpipePeer() {
  Gl& g = *gl_;
  OSMesaMakeCurrent(g.context, g.buffer.data(), GL_UNSIGNED_BYTE, g.width, g.height);
  g.release_meshes();
  glDeleteProgram(g.program);
  OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
  OSMesaDestroyContext(g.context);
}

std::string LlvmpipePeer::renderer() const {
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return r ? r : "";
}

void LlvmpipePeer::set_scene(const Scene& scene) {
  Gl& g = *gl_;
  if (scene.width != g.width || scene.height != g.height)
    throw PeerError("llvmpipe: scene " + scene.name + " is " + std::to_string(scene.width) + "x" +
                    std::to_string(scene.height) + ", the peer " + std::to_string(g.width) + "x" +
                    std::to_string(g.height));
  OSMesaMakeCurrent(g.context, g.buffer.data(), GL_UNSIGNED_BYTE, g.width, g.height);
  g.release_meshes();
  for (const MeshSpec& spec : scene.meshes) {
    const Mesh& mesh = spec.mesh;
    std::vector<float> vertices;  // position, normal
    vertices.reserve(mesh.positions.size() * 6);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
      for (const glm::dvec3& v : {mesh.positions[i], mesh.normals[i]})
        for (int k = 0; k < 3; ++k) vertices.push_back(static_cast<float>(v[k]));
    std::vector<GLuint> indices;
    indices.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    Gl::MeshBuffers b;
    b.model = spec.transform.matrix();
    b.index_count = static_cast<GLsizei>(indices.size());
    glGenVertexArrays(1, &b.vao);
    glBindVertexArray(b.vao);
    glGenBuffers(1, &b.vertices);
    glBindBuffer(GL_ARRAY_BUFFER, b.vertices);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
                 vertices.data(), GL_STATIC_DRAW);
    glGenBuffers(1, &b.indices);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.indices);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(GLuint)),
                 indices.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                          reinterpret_cast<const void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    g.meshes.push_back(b);
  }
  glBindVertexArray(0);

  const std::vector<EyeLight> lights = eye_lights(scene);
  glDeleteProgram(g.program);  // the previous scene's (0: none)
  g.program = 0;
  g.loaded = false;
  g.program = link_program(lights.size());
  glUseProgram(g.program);
  const glm::mat4 projection(projection_matrix(scene.camera, g.width, g.height));
  glUniformMatrix4fv(g.uniform("projection"), 1, GL_FALSE, glm::value_ptr(projection));
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const std::string at = "[" + std::to_string(i) + "]";
    glUniform1i(g.uniform(("light_is_point" + at).c_str()),
                lights[i].kind == LightKind::Point ? 1 : 0);
    const glm::vec3 v(lights[i].vector), c(lights[i].colour);
    glUniform3fv(g.uniform(("light_vector" + at).c_str()), 1, glm::value_ptr(v));
    glUniform3fv(g.uniform(("light_colour" + at).c_str()), 1, glm::value_ptr(c));
  }
  const Material& m = scene.material;
  const glm::vec3 colour(m.colour);
  glUniform3fv(g.uniform("colour"), 1, glm::value_ptr(colour));
  glUniform1f(g.uniform("ka"), static_cast<float>(m.ka));
  glUniform1f(g.uniform("kd"), static_cast<float>(m.kd));
  glUniform1f(g.uniform("ks"), static_cast<float>(m.ks));
  glUniform1f(g.uniform("n"), static_cast<float>(m.n));
  glUniform1i(g.uniform("eye_at_infinity"), eye_at_infinity(scene.camera) ? 1 : 0);
  if (scene.cull_backfaces)
    glEnable(GL_CULL_FACE);
  else
    glDisable(GL_CULL_FACE);
  glClearColor(static_cast<float>(scene.background.r), static_cast<float>(scene.background.g),
               static_cast<float>(scene.background.b), 0.0f);
  glClearDepth(1.0);
  check_gl("set_scene");
  g.scene = scene;
  g.loaded = true;
}

PeerFrame LlvmpipePeer::render(double model_rotation_radians) {
  Gl& g = *gl_;
  if (!g.loaded) throw PeerError("llvmpipe: render before set_scene");
  OSMesaMakeCurrent(g.context, g.buffer.data(), GL_UNSIGNED_BYTE, g.width, g.height);
  const glm::dmat4 view = view_matrix(g.scene.camera) * rotation_about_y(model_rotation_radians);
  const GLint mv_at = g.uniform("model_view"), normal_at = g.uniform("normal_matrix");

  const auto start = std::chrono::steady_clock::now();
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  for (const Gl::MeshBuffers& b : g.meshes) {
    const glm::mat4 mv(view * b.model);
    const glm::mat3 normal(mv);
    glUniformMatrix4fv(mv_at, 1, GL_FALSE, glm::value_ptr(mv));
    glUniformMatrix3fv(normal_at, 1, GL_FALSE, glm::value_ptr(normal));
    glBindVertexArray(b.vao);
    glDrawElements(GL_TRIANGLES, b.index_count, GL_UNSIGNED_INT, nullptr);
  }
  glFinish();
  const auto stop = std::chrono::steady_clock::now();
  check_gl("render");

  PeerFrame f;
  f.width = g.width;
  f.height = g.height;
  f.render_ms = std::chrono::duration<double, std::milli>(stop - start).count();
  const std::size_t pixels = static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height);
  f.rgb.resize(pixels * 3);
  f.covered.resize(pixels);
  for (std::size_t i = 0; i < pixels; ++i) {
    for (int k = 0; k < 3; ++k) f.rgb[i * 3 + k] = g.buffer[i * 4 + k];
    f.covered[i] = g.buffer[i * 4 + 3] != 0 ? 1 : 0;
  }
  return f;
}

}  // namespace tp::host
