#include "cgamesh/render/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <epoxy/gl.h>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cgamesh/errors.hpp"

namespace cgamesh::render {
namespace {

// Meshes: smooth or flat normals, per-vertex colours, a base colour texture; a geometry shader
// gives each fragment its face normal and its distances to the triangle's edges in pixels
// (single-pass wireframe, Bærentzen et al. 2006).
constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
layout(location = 3) in vec2 a_uv;
uniform mat4 u_view_projection;
out vec3 vg_world;
out vec3 vg_normal;
out vec3 vg_color;
out vec2 vg_uv;
void main() {
  vg_world = a_position;
  vg_normal = a_normal;
  vg_color = a_color;
  vg_uv = a_uv;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
}
)";

constexpr const char* kMeshGeometry = R"(#version 330 core
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
uniform vec2 u_viewport;
in vec3 vg_world[];
in vec3 vg_normal[];
in vec3 vg_color[];
in vec2 vg_uv[];
out vec3 f_world;
out vec3 f_normal;
out vec3 f_color;
out vec2 f_uv;
flat out vec3 f_face_normal;
noperspective out vec3 f_edge_distance;
void main() {
  vec3 face = cross(vg_world[1] - vg_world[0], vg_world[2] - vg_world[0]);
  vec2 p[3];
  for (int i = 0; i < 3; ++i) p[i] = u_viewport * gl_in[i].gl_Position.xy / gl_in[i].gl_Position.w * 0.5;
  float area = abs((p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y));
  float h[3];
  h[0] = area / max(length(p[2] - p[1]), 1e-6);
  h[1] = area / max(length(p[2] - p[0]), 1e-6);
  h[2] = area / max(length(p[1] - p[0]), 1e-6);
  for (int i = 0; i < 3; ++i) {
    f_world = vg_world[i];
    f_normal = vg_normal[i];
    f_color = vg_color[i];
    f_uv = vg_uv[i];
    f_face_normal = face;
    f_edge_distance = vec3(i == 0 ? h[0] : 0.0, i == 1 ? h[1] : 0.0, i == 2 ? h[2] : 0.0);
    // Behind the eye the pixel distances are meaningless: no wire there.
    if (gl_in[0].gl_Position.w <= 0.0 || gl_in[1].gl_Position.w <= 0.0 || gl_in[2].gl_Position.w <= 0.0)
      f_edge_distance = vec3(1e6);
    gl_Position = gl_in[i].gl_Position;
    EmitVertex();
  }
  EndPrimitive();
}
)";

// The fragment shader follows the geometry shader (wireframe), or the vertex shader directly:
// then the face normal comes from screen-space derivatives, which is much faster on llvmpipe.
constexpr const char* kMeshFragment = R"(
#ifdef WITH_GEOMETRY
in vec3 f_world;
in vec3 f_normal;
in vec3 f_color;
in vec2 f_uv;
flat in vec3 f_face_normal;
noperspective in vec3 f_edge_distance;
#else
in vec3 vg_world;
in vec3 vg_normal;
in vec3 vg_color;
in vec2 vg_uv;
#define f_world vg_world
#define f_normal vg_normal
#define f_color vg_color
#define f_uv vg_uv
#define f_face_normal ((gl_FrontFacing ? 1.0 : -1.0) * cross(dFdx(vg_world), dFdy(vg_world)))
#define f_edge_distance vec3(1e6)
#endif
uniform vec3 u_eye;
uniform vec3 u_light;
uniform vec4 u_base_color;
uniform bool u_smooth;
uniform bool u_has_colors;
uniform bool u_has_texture;
uniform sampler2D u_texture;
uniform float u_ambient;
uniform vec3 u_back_color;
uniform bool u_wireframe;
uniform vec3 u_wire_color;
out vec4 color;
void main() {
  vec3 n = u_smooth ? f_normal : f_face_normal;
  n = length(n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
  if (!gl_FrontFacing) n = -n;
  vec3 base = u_base_color.rgb;
  if (u_has_colors) base *= f_color;
  if (u_has_texture) base *= texture(u_texture, f_uv).rgb;
  vec3 v = normalize(u_eye - f_world);
  float diffuse = max(dot(n, u_light), 0.0);
  float fill = 0.25 * max(dot(n, v), 0.0);
  float specular = 0.12 * pow(max(dot(reflect(-u_light, n), v), 0.0), 24.0);
  vec3 c = base * (u_ambient + (1.0 - u_ambient) * min(diffuse + fill, 1.0)) + vec3(specular);
  if (!gl_FrontFacing) c = mix(c, u_back_color * (0.35 + 0.65 * diffuse), 0.6);
  if (u_wireframe) {
    float d = min(f_edge_distance.x, min(f_edge_distance.y, f_edge_distance.z));
    c = mix(c, u_wire_color, 0.8 * (1.0 - smoothstep(0.0, 1.0, d)));
  }
  color = vec4(c, 1.0);
}
)";

// Overlays: lines widened to quads u_size pixels wide, points as discs u_size pixels across.
constexpr const char* kOverlayVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_projection;
uniform float u_size;
void main() {
  gl_Position = u_view_projection * vec4(a_position, 1.0);
  gl_PointSize = u_size;
}
)";

constexpr const char* kLineGeometry = R"(#version 330 core
layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
uniform vec2 u_viewport;
uniform float u_size;
void main() {
  vec4 a = gl_in[0].gl_Position, b = gl_in[1].gl_Position;
  if (a.w <= 0.0 || b.w <= 0.0) return;
  vec2 d = b.xy / b.w - a.xy / a.w;
  d = length(d * u_viewport) > 0.0 ? normalize(d * u_viewport) : vec2(1.0, 0.0);
  vec2 offset = vec2(-d.y, d.x) * u_size / u_viewport;
  gl_Position = a + vec4(offset * a.w, 0.0, 0.0); EmitVertex();
  gl_Position = a - vec4(offset * a.w, 0.0, 0.0); EmitVertex();
  gl_Position = b + vec4(offset * b.w, 0.0, 0.0); EmitVertex();
  gl_Position = b - vec4(offset * b.w, 0.0, 0.0); EmitVertex();
  EndPrimitive();
}
)";

constexpr const char* kOverlayFragment = R"(#version 330 core
uniform vec3 u_color;
uniform bool u_round;
out vec4 color;
void main() {
  if (u_round && length(gl_PointCoord - vec2(0.5)) > 0.5) discard;
  color = vec4(u_color, 1.0);
}
)";

GLuint compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  // Sources that start with a newline get the version line and, after a geometry stage, its define.
  const std::string text = source[0] == '\n' ? std::string("#version 330 core") + source : source;
  const char* c = text.c_str();
  glShaderSource(s, 1, &c, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw PlatformError(std::string("renderer: a shader does not compile on this OpenGL: ") + log);
  }
  return s;
}

GLuint link(std::initializer_list<std::pair<GLenum, const char*>> stages) {
  const GLuint p = glCreateProgram();
  std::vector<GLuint> shaders;
  try {
    for (const auto& [type, source] : stages) {
      shaders.push_back(compile(type, source));
      glAttachShader(p, shaders.back());
    }
  } catch (const PlatformError&) {
    for (const GLuint s : shaders) glDeleteShader(s);
    glDeleteProgram(p);
    throw;
  }
  glLinkProgram(p);
  for (const GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw PlatformError(std::string("renderer: a shader program does not link: ") + log);
  }
  return p;
}

void check_mesh(const DrawMesh& m, std::size_t index) {
  const std::string what = "renderer: mesh " + std::to_string(index);
  const Eigen::Index nv = m.positions.rows();
  const auto rows_ok = [nv](Eigen::Index rows) { return rows == 0 || rows == nv; };
  if (!rows_ok(m.normals.rows()) || !rows_ok(m.colors.rows()) || !rows_ok(m.uvs.rows()))
    throw InvalidInputError(what + ": normals, colours and uvs need one row per vertex (" + std::to_string(nv) + ")");
  if (!m.positions.allFinite()) throw InvalidInputError(what + ": a position is NaN or infinite");
  if (m.faces.rows() > 0 && (m.faces.minCoeff() < 0 || m.faces.maxCoeff() >= nv))
    throw InvalidInputError(what + ": a face index is outside its " + std::to_string(nv) + " vertices");
  if (m.texture && (m.texture->width <= 0 || m.texture->height <= 0 ||
                    m.texture->rgba.size() != static_cast<std::size_t>(m.texture->width) * m.texture->height * 4))
    throw InvalidInputError(what + ": the texture's pixels do not match its size");
}

Eigen::Matrix4f view_projection(const Camera& camera, const Box& box, double aspect) {
  double near = 0, far = 0;
  depth_range(camera, box, near, far);
  return (projection_matrix(camera, aspect, near, far) * view_matrix(camera)).cast<float>();
}

/// A framebuffer with colour and depth renderbuffers.
struct Framebuffer {
  GLuint fbo = 0, color = 0, depth = 0;

  Framebuffer(int width, int height, int samples, bool with_depth) {
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenRenderbuffers(1, &color);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    if (with_depth) {
      glGenRenderbuffers(1, &depth);
      glBindRenderbuffer(GL_RENDERBUFFER, depth);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    }
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      release();
      throw PlatformError("renderer: the driver cannot make a " + std::to_string(width) + "x" + std::to_string(height) +
                          " framebuffer");
    }
  }
  ~Framebuffer() { release(); }
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  void release() {
    if (fbo) glDeleteFramebuffers(1, &fbo);
    if (color) glDeleteRenderbuffers(1, &color);
    if (depth) glDeleteRenderbuffers(1, &depth);
    fbo = color = depth = 0;
  }
};

}  // namespace

void validate(const RenderOptions& o) {
  if (o.width < 1 || o.height < 1 || o.width > kMaxImageSide || o.height > kMaxImageSide)
    throw InvalidInputError("render: the picture size must be 1 to " + std::to_string(kMaxImageSide) +
                            " pixels a side, got " + std::to_string(o.width) + "x" + std::to_string(o.height));
  if (o.samples < 1 || o.samples > 16) throw InvalidInputError("render: samples must be 1 to 16");
  if (!o.background.allFinite() || !o.wire_color.allFinite() || !o.back_face_color.allFinite() ||
      !std::isfinite(o.ambient))
    throw InvalidInputError("render: colours must be finite");
}

struct Renderer::State {
  GLuint mesh_program = 0, wire_program = 0, line_program = 0, point_program = 0;
  GLuint vao = 0;
  std::vector<GLuint> buffers;  // positions, normals, colours, uvs, indices: reused between draws
  /// Textures uploaded once per image, while the image lives (a viewer redraws every frame).
  std::vector<std::pair<std::weak_ptr<const Image>, GLuint>> textures;

  ~State() {
    for (const auto& [image, id] : textures) glDeleteTextures(1, &id);
    if (!buffers.empty()) glDeleteBuffers(static_cast<GLsizei>(buffers.size()), buffers.data());
    if (vao) glDeleteVertexArrays(1, &vao);
    for (const GLuint p : {mesh_program, wire_program, line_program, point_program})
      if (p) glDeleteProgram(p);
  }

  /// The texture of `image`, uploaded (with mipmaps) the first time it is drawn.
  GLuint texture(const std::shared_ptr<const Image>& image) {
    std::erase_if(textures, [](const auto& t) {
      if (!t.first.expired()) return false;
      glDeleteTextures(1, &t.second);
      return true;
    });
    for (const auto& [known, id] : textures)
      if (known.lock() == image) return id;
    GLuint id = 0;
    glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_2D, id);
    // Image rows are top first; OpenGL's v = 0 is the bottom row.
    std::vector<std::uint8_t> flipped(image->rgba.size());
    const std::size_t row = static_cast<std::size_t>(image->width) * 4;
    for (int y = 0; y < image->height; ++y)
      std::copy_n(image->pixel(0, y), row, flipped.data() + row * static_cast<std::size_t>(image->height - 1 - y));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image->width, image->height, 0, GL_RGBA, GL_UNSIGNED_BYTE, flipped.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    textures.emplace_back(image, id);
    return id;
  }

  GLint uniform(GLuint program, const char* name) const { return glGetUniformLocation(program, name); }

  void attribute(GLuint location, int columns, const float* data, Eigen::Index rows, float fallback) {
    if (rows > 0) {
      glBindBuffer(GL_ARRAY_BUFFER, buffers[location]);
      glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(rows * columns * sizeof(float)), data, GL_STREAM_DRAW);
      glVertexAttribPointer(location, columns, GL_FLOAT, GL_FALSE, 0, nullptr);
      glEnableVertexAttribArray(location);
    } else {
      glDisableVertexAttribArray(location);
      glVertexAttrib4f(location, fallback, fallback, fallback, 1.0f);
    }
  }
};

Renderer::Renderer() {
  if (epoxy_gl_version() < 33)
    throw PlatformError("renderer: needs OpenGL 3.3 core; the current context has " +
                        std::to_string(epoxy_gl_version() / 10) + "." + std::to_string(epoxy_gl_version() % 10));
  state_ = std::make_unique<State>();
  const std::string wire_fragment = std::string("\n#define WITH_GEOMETRY") + kMeshFragment;
  state_->mesh_program = link({{GL_VERTEX_SHADER, kMeshVertex}, {GL_FRAGMENT_SHADER, kMeshFragment}});
  state_->wire_program = link({{GL_VERTEX_SHADER, kMeshVertex},
                               {GL_GEOMETRY_SHADER, kMeshGeometry},
                               {GL_FRAGMENT_SHADER, wire_fragment.c_str()}});
  state_->line_program = link({{GL_VERTEX_SHADER, kOverlayVertex},
                               {GL_GEOMETRY_SHADER, kLineGeometry},
                               {GL_FRAGMENT_SHADER, kOverlayFragment}});
  state_->point_program = link({{GL_VERTEX_SHADER, kOverlayVertex}, {GL_FRAGMENT_SHADER, kOverlayFragment}});
  glGenVertexArrays(1, &state_->vao);
  state_->buffers.resize(5);
  glGenBuffers(5, state_->buffers.data());
}

Renderer::~Renderer() = default;

void Renderer::draw(const Scene& scene, const Camera& camera, const RenderOptions& o) {
  validate(o);
  validate(camera);
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) check_mesh(scene.meshes[i], i);
  State& s = *state_;
  const Box box = scene.bounds();
  const Eigen::Matrix4f vp = view_projection(camera, box, static_cast<double>(o.width) / o.height);
  // The key light comes from above, left and behind the eye (view space (−0.4, 0.6, 0.7)).
  const Eigen::Matrix3d to_world = view_matrix(camera).topLeftCorner<3, 3>().transpose();
  const Eigen::Vector3f light = (to_world * Eigen::Vector3d(-0.4, 0.6, 0.7).normalized()).cast<float>();
  const Eigen::Vector3f eye = camera.eye.cast<float>();

  glViewport(0, 0, o.width, o.height);
  glClearColor(o.background.x(), o.background.y(), o.background.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_CULL_FACE);
  glBindVertexArray(s.vao);

  const GLuint mp = o.wireframe ? s.wire_program : s.mesh_program;
  glUseProgram(mp);
  glUniformMatrix4fv(s.uniform(mp, "u_view_projection"), 1, GL_FALSE, vp.data());
  glUniform2f(s.uniform(mp, "u_viewport"), static_cast<float>(o.width), static_cast<float>(o.height));
  glUniform3fv(s.uniform(mp, "u_eye"), 1, eye.data());
  glUniform3fv(s.uniform(mp, "u_light"), 1, light.data());
  glUniform1f(s.uniform(mp, "u_ambient"), o.ambient);
  glUniform3fv(s.uniform(mp, "u_back_color"), 1, o.back_face_color.data());
  glUniform1i(s.uniform(mp, "u_wireframe"), o.wireframe ? 1 : 0);
  glUniform3fv(s.uniform(mp, "u_wire_color"), 1, o.wire_color.data());
  glUniform1i(s.uniform(mp, "u_texture"), 0);
  for (const DrawMesh& m : scene.meshes) {
    if (m.faces.rows() == 0) continue;
    s.attribute(0, 3, m.positions.data(), m.positions.rows(), 0);
    s.attribute(1, 3, m.normals.data(), m.normals.rows(), 0);
    s.attribute(2, 3, m.colors.data(), m.colors.rows(), 1);
    const bool textured = m.texture && m.uvs.rows() > 0;
    s.attribute(3, 2, m.uvs.data(), textured ? m.uvs.rows() : 0, 0);
    if (textured) {
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, s.texture(m.texture));
    }
    glUniform4fv(s.uniform(mp, "u_base_color"), 1, m.base_color.data());
    glUniform1i(s.uniform(mp, "u_smooth"), m.normals.rows() > 0 ? 1 : 0);
    glUniform1i(s.uniform(mp, "u_has_colors"), m.colors.rows() > 0 ? 1 : 0);
    glUniform1i(s.uniform(mp, "u_has_texture"), textured ? 1 : 0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, s.buffers[4]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(m.faces.size() * sizeof(int)), m.faces.data(),
                 GL_STREAM_DRAW);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m.faces.size()), GL_UNSIGNED_INT, nullptr);
  }
  for (GLuint a = 1; a < 4; ++a) glDisableVertexAttribArray(a);

  const auto overlay = [&](GLuint program, const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& color,
                           float size, bool on_top, GLenum primitive) {
    if (points.empty()) return;
    glUseProgram(program);
    glUniformMatrix4fv(s.uniform(program, "u_view_projection"), 1, GL_FALSE, vp.data());
    glUniform2f(s.uniform(program, "u_viewport"), static_cast<float>(o.width), static_cast<float>(o.height));
    glUniform1f(s.uniform(program, "u_size"), size);
    glUniform3fv(s.uniform(program, "u_color"), 1, color.data());
    glUniform1i(s.uniform(program, "u_round"), primitive == GL_POINTS ? 1 : 0);
    if (on_top)
      glDisable(GL_DEPTH_TEST);
    else
      glEnable(GL_DEPTH_TEST);
    s.attribute(0, 3, points.front().data(), static_cast<Eigen::Index>(points.size()), 0);
    glDrawArrays(primitive, 0, static_cast<GLsizei>(points.size()));
  };
  glEnable(GL_PROGRAM_POINT_SIZE);
  for (const LineSet& l : scene.lines) overlay(s.line_program, l.points, l.color, l.width_pixels, l.on_top, GL_LINES);
  for (const PointSet& p : scene.points)
    overlay(s.point_program, p.points, p.color, p.size_pixels, p.on_top, GL_POINTS);
  glEnable(GL_DEPTH_TEST);
  glBindVertexArray(0);
  glUseProgram(0);
}

Image Renderer::render(const Scene& scene, const Camera& camera, const RenderOptions& o) {
  validate(o);
  GLint max_size = 0, max_samples = 1;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (o.width > max_size || o.height > max_size)
    throw PlatformError("render: this OpenGL makes pictures of at most " + std::to_string(max_size) +
                        " pixels a side, asked for " + std::to_string(o.width) + "x" + std::to_string(o.height));
  const int samples = std::min(o.samples, static_cast<int>(max_samples));
  const Framebuffer multi(o.width, o.height, samples > 1 ? samples : 0, true);
  draw(scene, camera, o);
  const Framebuffer resolved(o.width, o.height, 0, false);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, multi.fbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolved.fbo);
  glBlitFramebuffer(0, 0, o.width, o.height, 0, 0, o.width, o.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolved.fbo);
  Image out{o.width, o.height, {}};
  out.rgba.resize(static_cast<std::size_t>(o.width) * static_cast<std::size_t>(o.height) * 4);
  std::vector<std::uint8_t> bottom_up(out.rgba.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const std::size_t row = static_cast<std::size_t>(o.width) * 4;
  for (int y = 0; y < o.height; ++y)
    std::copy_n(bottom_up.data() + row * static_cast<std::size_t>(o.height - 1 - y), row, out.pixel(0, y));
  for (std::size_t i = 3; i < out.rgba.size(); i += 4) out.rgba[i] = 255;
  if (const GLenum e = glGetError(); e != GL_NO_ERROR)
    throw PlatformError("render: OpenGL error " + std::to_string(e) + " while drawing");
  return out;
}

}  // namespace cgamesh::render
