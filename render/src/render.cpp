#include "owval/render/render.hpp"

#include <GL/gl.h>
#include <GL/osmesa.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "code_pages.hpp"
#include "mp4_writer.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/one_line.hpp"
#include "owval/base/progress.hpp"
#include "owval/render/video_check.hpp"
#include "side_by_side.hpp"
#include "text.hpp"
#include "worm_camera.hpp"

namespace owval::render {
namespace {

using Vec3 = std::array<float, 3>;

Vec3 Sub(Vec3 a, Vec3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 Cross(Vec3 a, Vec3 b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
float Dot(Vec3 a, Vec3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 Normalize(Vec3 a) {
  const float n = std::sqrt(Dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}

constexpr float kFieldOfViewDeg = 35.0f;
const unsigned char kBackground[3] = {250, 250, 250};
const unsigned char kTextColour[3] = {20, 20, 20};

// Colours by particle kind: liquid blue, elastic green, boundary grey.
void KindColour(ParticleKind kind, float out[3]) {
  switch (kind) {
    case ParticleKind::kLiquid:
      out[0] = 0.15f, out[1] = 0.40f, out[2] = 0.95f;
      break;
    case ParticleKind::kElastic:
      out[0] = 0.10f, out[1] = 0.70f, out[2] = 0.25f;
      break;
    case ParticleKind::kBoundary:
      out[0] = 0.55f, out[1] = 0.55f, out[2] = 0.55f;
      break;
  }
}

// An off-screen OpenGL canvas. OSMesa renders into our own buffer, top row first.
class Canvas {
 public:
  Canvas(int width, int height)
      : width_(width), height_(height), pixels_(std::size_t(width) * height * 4) {
    context_ = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
    if (!context_) throw EnvironmentError("OSMesa could not create an off-screen context");
    if (!OSMesaMakeCurrent(context_, pixels_.data(), GL_UNSIGNED_BYTE, width, height))
      throw EnvironmentError("OSMesa could not bind the frame buffer");
    OSMesaPixelStore(OSMESA_Y_UP, 0);
    MakeSphereSprite();
  }
  ~Canvas() { OSMesaDestroyContext(context_); }

  void Clear() {
    glViewport(0, 0, width_, height_);
    glClearColor(kBackground[0] / 255.f, kBackground[1] / 255.f, kBackground[2] / 255.f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }

  // Draws one frame of a trajectory into the panel whose left edge is at x0 (pixels).
  void DrawPanel(const Trajectory& t, std::size_t frame, const Camera& camera, int x0,
                 int panel_width, const RenderOptions& o, float point_size) {
    glViewport(x0, 0, panel_width, height_);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(camera.projection.data());
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(camera.view.data());
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_TEXTURE_2D);
    glEnable(GL_POINT_SPRITE);
    glTexEnvi(GL_POINT_SPRITE, GL_COORD_REPLACE, GL_TRUE);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glEnable(GL_ALPHA_TEST);
    glAlphaFunc(GL_GREATER, 0.5f);
    glPointSize(point_size);
    // Opaque particles first, then translucent ones without depth writes.
    DrawKinds(t, frame, o, /*translucent=*/false);
    DrawConnections(t, frame, o);
    if (o.draw_box) DrawBoxEdges(t.box);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    DrawKinds(t, frame, o, /*translucent=*/true);
    if (o.draw_box) DrawFloor(t.box);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }

  std::vector<unsigned char>& Pixels() {
    glFinish();
    return pixels_;
  }

 private:
  void DrawKinds(const Trajectory& t, std::size_t frame, const RenderOptions& o, bool translucent) {
    vertices_.clear();
    colours_.clear();
    for (std::size_t p = 0; p < t.particle_count(); ++p) {
      const ParticleKind kind = KindOf(t.type[p]);
      float alpha = 1.0f;
      if (kind == ParticleKind::kBoundary) {
        if (o.boundary == BoundaryMode::kHidden) continue;
        if (o.boundary == BoundaryMode::kTranslucent) alpha = 0.15f;
      } else if (kind == ParticleKind::kLiquid) {
        // The worm view shows the body through its liquid.
        alpha = o.view == "worm" ? std::min(o.liquid_opacity, 0.3f) : o.liquid_opacity;
      }
      if ((alpha < 1.0f) != translucent) continue;
      const float* x = t.position(frame, p);
      vertices_.insert(vertices_.end(), {x[0], x[1], x[2]});
      float c[3] = {0, 0, 0};
      KindColour(kind, c);
      colours_.insert(colours_.end(), {c[0], c[1], c[2], alpha});
    }
    if (vertices_.empty()) return;
    glAlphaFunc(GL_GREATER, translucent ? 0.01f : 0.5f);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, vertices_.data());
    glColorPointer(4, GL_FLOAT, 0, colours_.data());
    glDrawArrays(GL_POINTS, 0, GLsizei(vertices_.size() / 3));
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
  }

  void DrawConnections(const Trajectory& t, std::size_t frame, const RenderOptions& o) {
    if (o.connections.empty()) return;
    vertices_.clear();
    for (const auto& [a, b] : o.connections) {
      if (a >= t.particle_count() || b >= t.particle_count()) continue;
      const float* x = t.position(frame, a);
      const float* y = t.position(frame, b);
      vertices_.insert(vertices_.end(), {x[0], x[1], x[2], y[0], y[1], y[2]});
    }
    DrawLines(0.05f, 0.35f, 0.1f, 1.0f);
  }

  static bool HasWalls(const Box& b) {
    return b.extent(0) > 0 && b.extent(1) > 0 && b.extent(2) > 0;
  }

  // The twelve edges of the box, so a falling body has a floor and walls to be seen against.
  void DrawBoxEdges(const Box& b) {
    if (!HasWalls(b)) return;
    vertices_.clear();
    const float xs[2] = {b.xmin, b.xmax}, ys[2] = {b.ymin, b.ymax}, zs[2] = {b.zmin, b.zmax};
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        vertices_.insert(vertices_.end(), {b.xmin, ys[i], zs[j], b.xmax, ys[i], zs[j]});
        vertices_.insert(vertices_.end(), {xs[i], b.ymin, zs[j], xs[i], b.ymax, zs[j]});
        vertices_.insert(vertices_.end(), {xs[i], ys[j], b.zmin, xs[i], ys[j], b.zmax});
      }
    DrawLines(0.35f, 0.35f, 0.35f, 1.0f);
  }

  // The floor (y = ymin: gravity points along -y) as a faint plane.
  void DrawFloor(const Box& b) {
    if (!HasWalls(b)) return;
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_ALPHA_TEST);
    glColor4f(0.45f, 0.40f, 0.35f, 0.18f);
    glBegin(GL_QUADS);
    glVertex3f(b.xmin, b.ymin, b.zmin);
    glVertex3f(b.xmax, b.ymin, b.zmin);
    glVertex3f(b.xmax, b.ymin, b.zmax);
    glVertex3f(b.xmin, b.ymin, b.zmax);
    glEnd();
    glEnable(GL_TEXTURE_2D);
    glEnable(GL_ALPHA_TEST);
  }

  // vertices_ as GL_LINES pairs in one colour.
  void DrawLines(float r, float g, float b, float a) {
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_ALPHA_TEST);
    glColor4f(r, g, b, a);
    glLineWidth(1.0f);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, vertices_.data());
    glDrawArrays(GL_LINES, 0, GLsizei(vertices_.size() / 3));
    glDisableClientState(GL_VERTEX_ARRAY);
    glEnable(GL_TEXTURE_2D);
    glEnable(GL_ALPHA_TEST);
  }

  // A 64x64 sprite of a lit sphere: alpha 0 outside the disc, Lambert shading inside.
  void MakeSphereSprite() {
    constexpr int n = 64;
    std::vector<unsigned char> sprite(n * n * 4);
    const Vec3 light = Normalize({-0.4f, 0.5f, 0.8f});
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const float u = (x + 0.5f) / n * 2 - 1, v = (y + 0.5f) / n * 2 - 1, r2 = u * u + v * v;
        unsigned char* p = &sprite[std::size_t(y * n + x) * 4];
        const float shade =
            r2 < 1
                ? 0.35f +
                      0.65f * std::max(0.0f, Dot({u, -v, std::sqrt(1 - std::min(r2, 1.0f))}, light))
                : 0;
        p[0] = p[1] = p[2] = static_cast<unsigned char>(255 * std::min(1.0f, shade));
        p[3] = r2 < 1 ? 255 : 0;
      }
    }
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, n, n, 0, GL_RGBA, GL_UNSIGNED_BYTE, sprite.data());
  }

  OSMesaContext context_ = nullptr;
  int width_, height_;
  std::vector<unsigned char> pixels_;
  std::vector<float> vertices_, colours_;
  GLuint texture_ = 0;
};

// first: the trajectory's frame 0.
float PointSize(const FrameRef& first, const RenderOptions& o, int panel_height) {
  if (o.point_size_px > 0) return o.point_size_px;
  // A particle is about r0 = 1.67 cu across; the box (the worm in the worm view) spans its
  // diagonal on screen.
  const Trajectory& t = first.trajectory;
  const float diagonal =
      o.view == "worm"
          ? 2 * internal::WormHalfExtent(t, first.frame, float(o.width) / float(o.height))
          : std::sqrt(t.box.extent(0) * t.box.extent(0) + t.box.extent(1) * t.box.extent(1) +
                      t.box.extent(2) * t.box.extent(2));
  return std::clamp(1.67f / diagonal * float(panel_height) * 1.1f, 2.0f, 24.0f);
}

std::string Format(const char* format, double value) {
  char b[96];
  std::snprintf(b, sizeof b, format, value);
  return b;
}

// Text rows from the top of a panel (the bottom is where a browser's video controls sit): the
// title (when there is one), then the panel's name, its time, its tracked value, the difference.
int Row(const RenderOptions& o, int row) { return (o.title.empty() ? 28 : 56) + 24 * row; }

void Label(internal::TextPainter& text, std::vector<unsigned char>& rgba, const RenderOptions& o,
           int x0, const std::string& panel, const FrameRef& f) {
  const Trajectory& t = f.trajectory;
  const std::size_t frame = f.frame;
  const int w = o.width, h = o.height;
  text.Draw(rgba, w, h, x0 + 12, Row(o, 0), panel, 20, kTextColour);
  text.Draw(rgba, w, h, x0 + 12, Row(o, 1), Format("t = %.3f ms", t.time_s[frame] * 1e3), 18,
            kTextColour);
  if (o.tracking) {
    const std::string label =
        o.tracking->Describe() + " = " + Format("%.4f cu", o.tracking->ValueAt(t, frame));
    text.Draw(rgba, w, h, x0 + 12, Row(o, 2), label, 18, kTextColour);
  }
}

void Title(internal::TextPainter& text, std::vector<unsigned char>& rgba, const RenderOptions& o) {
  if (!o.title.empty()) text.Draw(rgba, o.width, o.height, 12, 28, o.title, 18, kTextColour);
}

void WritePng(const std::filesystem::path& path, const std::vector<unsigned char>& rgba, int width,
              int height) {
  AtomicOutput out(path);
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = png_uint_32(width);
  image.height = png_uint_32(height);
  image.format = PNG_FORMAT_RGBA;
  if (!png_image_write_to_file(&image, out.temporary_path().c_str(), 0, rgba.data(), 0, nullptr))
    throw InputError(path.string(), 0, std::string("cannot write PNG: ") + image.message);
  out.Commit();
}

void CheckSize(const RenderOptions& o) {
  if (o.width < 16 || o.height < 16 || o.width > 8192 || o.height > 8192)
    throw InputError("frame size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                     " is out of range: expected 16 to 8192 pixels a side");
}

}  // namespace

void CheckVideoSize(const RenderOptions& o) {
  CheckSize(o);
  if (o.width % 2 || o.height % 2)
    throw InputError("--size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                     ": a video's width and height must be even (H.264 yuv420p)");
}

namespace {

// The MP4 writer, opened at the first frame: by then llvmpipe has compiled its shaders, and
// libLLVM's code leaves the resident set (code_pages.hpp) before libx264 allocates its frames.
// A 1280x720 render peaks at about 125 MB instead of 156-162 MB (issue 16, docs/benchmarks.md).
class Video {
 public:
  // path: the temporary written; shown: the destination, named in errors.
  // comment: the MP4's "comment" metadata ("" for none).
  Video(std::string path, const RenderOptions& o, std::string shown, std::string comment = "")
      : path_(std::move(path)),
        shown_(std::move(shown)),
        comment_(std::move(comment)),
        options_(o) {}
  void Add(const std::vector<unsigned char>& rgba) {
    Open();
    writer_->AddFrame(rgba);
  }
  // Finishes the file; returns the number of frames in it.
  std::size_t Finish() {
    Open();
    writer_->Finish();
    return writer_->frames();
  }

 private:
  void Open() {
    if (writer_) return;
    internal::ReleaseLibraryCode("libLLVM");
    writer_.emplace(path_, options_.width, options_.height, options_.fps, shown_, comment_);
  }
  std::string path_, shown_, comment_;
  RenderOptions options_;
  std::optional<internal::Mp4Writer> writer_;
};

// Reference left, candidate right, one camera from the reference's box, labelled.
class SideBySideFrame {
 public:
  // ref_first: the reference's frame 0 (for the point size).
  SideBySideFrame(const FrameRef& ref_first, const RenderOptions& o)
      : options_(o),
        canvas_(o.width, o.height),
        panel_(o.width / 2),
        camera_(Camera::FromBox(ref_first.trajectory.box, o.view, float(panel_) / float(o.height))),
        point_size_(PointSize(ref_first, o, o.height)) {}

  std::vector<unsigned char>& Compose(const FrameRef& ref, const FrameRef& cand) {
    canvas_.Clear();
    const Camera camera =
        options_.view == "worm"
            ? Camera::ForWorm(ref.trajectory, ref.frame, float(panel_) / float(options_.height))
            : camera_;
    canvas_.DrawPanel(ref.trajectory, ref.frame, camera, 0, panel_, options_, point_size_);
    canvas_.DrawPanel(cand.trajectory, cand.frame, camera, panel_, options_.width - panel_,
                      options_, point_size_);
    auto& rgba = canvas_.Pixels();
    Label(text_, rgba, options_, 0, options_.reference_label, ref);
    Label(text_, rgba, options_, panel_, options_.candidate_label, cand);
    return rgba;
  }
  internal::TextPainter& text() { return text_; }
  int panel() const { return panel_; }

 private:
  RenderOptions options_;
  Canvas canvas_;
  internal::TextPainter text_;
  int panel_;
  Camera camera_;
  float point_size_;
};

}  // namespace

namespace internal {

std::vector<std::size_t> SampleEvenly(std::size_t n, std::size_t cap) {
  std::vector<std::size_t> out;
  const std::size_t count = cap == 0 || cap >= n ? n : cap;
  for (std::size_t k = 0; k < count; ++k)
    out.push_back(count == n ? k : k * (n - 1) / std::max<std::size_t>(1, count - 1));
  return out;
}

struct SideBySideFrames::State {
  FrameSource &refs, &cands;
  RenderOptions options;
  std::vector<std::pair<std::size_t, std::size_t>> sampled;  // (reference, candidate) frames
  std::optional<SideBySideFrame> compose;
};

SideBySideFrames::SideBySideFrames(FrameSource& refs, FrameSource& cands, const RenderOptions& o)
    : state_(new State{refs, cands, o, {}, std::nullopt}) {
  // Frames paired by the one rule every comparison uses: only moments both runs recorded.
  const auto pairs = PairFramesByTime(refs.header(), cands.header());
  if (pairs.empty())
    throw InputError("the two trajectories share no frame time to show side by side");
  for (std::size_t k : SampleEvenly(pairs.size(), o.max_frames))
    state_->sampled.push_back(pairs[k]);
  state_->compose.emplace(refs.Frame(0), o);
}

SideBySideFrames::~SideBySideFrames() = default;

std::size_t SideBySideFrames::size() const { return state_->sampled.size(); }

const std::vector<unsigned char>& SideBySideFrames::Draw(std::size_t k) {
  const auto [fr, fc] = state_->sampled.at(k);
  const FrameRef ref = state_->refs.Frame(fr);
  auto& rgba = state_->compose->Compose(ref, state_->cands.Frame(fc));
  Title(state_->compose->text(), rgba, state_->options);
  return rgba;
}

const std::vector<unsigned char>& SideBySideFrames::DrawCandidateMoved(std::size_t k, Axis axis,
                                                                       float distance_cu) {
  const auto [fr, fc] = state_->sampled.at(k);
  const FrameRef cand = state_->cands.Frame(fc);
  Trajectory moved;
  moved.box = cand.trajectory.box;
  moved.type = cand.trajectory.type;
  moved.AppendFrame(cand.trajectory.time_s[cand.frame], cand.trajectory.position(cand.frame, 0));
  for (std::size_t p = 0; p < moved.particle_count(); ++p)
    if (KindOf(moved.type[p]) != ParticleKind::kBoundary)
      moved.position(0, p)[int(axis)] += distance_cu;
  const FrameRef ref = state_->refs.Frame(fr);
  auto& rgba = state_->compose->Compose(ref, FrameRef{moved, 0});
  Title(state_->compose->text(), rgba, state_->options);
  return rgba;
}

}  // namespace internal

BoundaryMode ParseBoundaryMode(const std::string& name) {
  if (name == "hidden") return BoundaryMode::kHidden;
  if (name == "translucent") return BoundaryMode::kTranslucent;
  if (name == "shown") return BoundaryMode::kShown;
  throw InputError("unknown boundary mode '" + name + "': expected hidden, translucent or shown");
}

const char* BoundaryModeName(BoundaryMode mode) {
  switch (mode) {
    case BoundaryMode::kHidden:
      return "hidden";
    case BoundaryMode::kTranslucent:
      return "translucent";
    case BoundaryMode::kShown:
      return "shown";
  }
  return "hidden";
}

Camera Camera::FromBox(const Box& box, const std::string& view, float aspect) {
  const Vec3 centre = {(box.xmin + box.xmax) / 2, (box.ymin + box.ymax) / 2,
                       (box.zmin + box.zmax) / 2};
  const float radius =
      0.5f * std::sqrt(box.extent(0) * box.extent(0) + box.extent(1) * box.extent(1) +
                       box.extent(2) * box.extent(2));
  Vec3 direction, up = {0, 1, 0};  // y is up: Sibernetic's gravity points along -y
  if (view == "iso")
    direction = Normalize({1.0f, 0.8f, 1.3f});
  else if (view == "side")
    direction = {1, 0, 0};
  else if (view == "front")
    direction = {0, 0, 1};
  else if (view == "top" || view == "worm")  // worm: ForWorm per frame; the box view as fallback
    direction = {0, 1, 0}, up = {0, 0, -1};
  else
    throw InputError("unknown view '" + view + "': expected iso, side, top, front or worm");
  const float fov = kFieldOfViewDeg * 3.14159265f / 180.0f;
  const float distance = radius / std::sin(fov / 2) * 1.05f;
  const Vec3 eye = {centre[0] + direction[0] * distance, centre[1] + direction[1] * distance,
                    centre[2] + direction[2] * distance};
  const Vec3 f = Normalize(Sub(centre, eye)), s = Normalize(Cross(f, up)), u = Cross(s, f);
  Camera c;
  c.view = {s[0], u[0], -f[0], 0, s[1],         u[1],         -f[1],       0,
            s[2], u[2], -f[2], 0, -Dot(s, eye), -Dot(u, eye), Dot(f, eye), 1};
  const float near = std::max(distance - radius * 1.5f, radius * 0.05f),
              far = distance + radius * 1.5f;
  const float top = near * std::tan(fov / 2), right = top * aspect;
  c.projection = {near / right,
                  0,
                  0,
                  0,
                  0,
                  near / top,
                  0,
                  0,
                  0,
                  0,
                  -(far + near) / (far - near),
                  -1,
                  0,
                  0,
                  -2 * far * near / (far - near),
                  0};
  return c;
}

std::array<float, 2> Camera::Project(const std::array<float, 3>& p, int width, int height) const {
  float eye[4], clip[4];
  for (int r = 0; r < 4; ++r)
    eye[r] = view[r] * p[0] + view[4 + r] * p[1] + view[8 + r] * p[2] + view[12 + r];
  for (int r = 0; r < 4; ++r)
    clip[r] = projection[r] * eye[0] + projection[4 + r] * eye[1] + projection[8 + r] * eye[2] +
              projection[12 + r] * eye[3];
  const float ndc_x = clip[0] / clip[3], ndc_y = clip[1] / clip[3];
  return {(ndc_x + 1) / 2 * float(width), (1 - ndc_y) / 2 * float(height)};
}

std::vector<unsigned char> RenderFrameRgba(const Trajectory& t, std::size_t frame,
                                           const RenderOptions& o) {
  CheckSize(o);
  Canvas canvas(o.width, o.height);
  canvas.Clear();
  const Camera camera = Camera::ForFrame(t, frame, o.view, float(o.width) / float(o.height));
  canvas.DrawPanel(t, frame, camera, 0, o.width, o, PointSize({t, 0}, o, o.height));
  return canvas.Pixels();
}

VideoSummary RenderVideo(FrameSource& frames, const RenderOptions& o,
                         const std::filesystem::path& out_mp4) {
  CheckVideoSize(o);
  CheckOutputPath(out_mp4);
  const Trajectory& t = frames.header();
  if (t.frame_count() == 0) throw InputError("the trajectory has no frame to render");
  AtomicOutput out(out_mp4);
  Canvas canvas(o.width, o.height);
  internal::TextPainter text;
  const Camera camera = Camera::FromBox(t.box, o.view, float(o.width) / float(o.height));
  const float size = PointSize(frames.Frame(0), o, o.height);
  const std::string producer =
      t.provenance.count("producer") ? t.provenance.at("producer") : "trajectory";
  Video video(out.temporary_path().string(), o, out_mp4.string());
  const auto sampled = internal::SampleEvenly(t.frame_count(), o.max_frames);
  Progress progress("render", sampled.size(), o.quiet);
  for (std::size_t k = 0; k < sampled.size(); ++k) {
    const FrameRef f = frames.Frame(sampled[k]);  // one frame in memory at a time
    canvas.Clear();
    canvas.DrawPanel(f.trajectory, f.frame,
                     o.view == "worm"
                         ? Camera::ForWorm(f.trajectory, f.frame, float(o.width) / o.height)
                         : camera,
                     0, o.width, o, size);
    auto& rgba = canvas.Pixels();
    Label(text, rgba, o, 0, producer, f);
    Title(text, rgba, o);
    video.Add(rgba);
    progress.Update(k + 1);
  }
  const std::size_t written = video.Finish();
  out.Commit();
  return {written, o.width, o.height, o.fps, double(written) / o.fps, {}};
}

VideoSummary RenderVideo(const Trajectory& t, const RenderOptions& o,
                         const std::filesystem::path& out_mp4) {
  const auto frames = MemoryFrameSource(t);
  return RenderVideo(*frames, o, out_mp4);
}

VideoSummary RenderSideBySide(FrameSource& refs, FrameSource& cands, const RenderOptions& o,
                              const std::filesystem::path& out_mp4) {
  CheckVideoSize(o);
  CheckOutputPath(out_mp4);
  const Trajectory& ref = refs.header();
  const Trajectory& cand = cands.header();
  if (ref.frame_count() == 0 || cand.frame_count() == 0)
    throw InputError("a trajectory has no frame to render");
  VideoSummary summary{0, o.width, o.height, o.fps, 0, {}};
  if (ref.time_step_s != cand.time_step_s || ref.log_step != cand.log_step)
    summary.notes.push_back("time step or log step differ (reference " +
                            Format("%g s", ref.time_step_s) + " x " + std::to_string(ref.log_step) +
                            ", candidate " + Format("%g s", cand.time_step_s) + " x " +
                            std::to_string(cand.log_step) + "): panels paired by simulation time");
  internal::SideBySideFrames frames(refs, cands, o);
  AtomicOutput out(out_mp4);
  // The options that decide the pixels go into the file, so that the checklist can draw the
  // frames again and see that the video shows its directory's two runs (CheckSideBySide).
  Video video(out.temporary_path().string(), o, out_mp4.string(),
              kSideBySideRecordPrefix + SideBySideRecord(o).dump());
  Progress progress("render sxs", frames.size(), o.quiet);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    video.Add(frames.Draw(k));
    progress.Update(k + 1);
  }
  summary.frames = video.Finish();
  out.Commit();
  summary.duration_s = double(summary.frames) / o.fps;
  return summary;
}

VideoSummary RenderSideBySide(const Trajectory& ref, const Trajectory& cand, const RenderOptions& o,
                              const std::filesystem::path& out_mp4) {
  const auto refs = MemoryFrameSource(ref), cands = MemoryFrameSource(cand);
  return RenderSideBySide(*refs, *cands, o, out_mp4);
}

namespace {

// The reference's range of the tracked value over the paired frames (a pass over them), as
// owval compare's frame gate scales it.
double PairedRange(FrameSource& refs, const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                   const Track& track) {
  std::vector<double> paired_ref;  // the reference over the common window, for the scale
  for (const auto& [fr, fc] : pairs) {
    const FrameRef f = refs.Frame(fr);
    paired_ref.push_back(track.ValueAt(f.trajectory, f.frame));
  }
  if (paired_ref.empty()) throw InputError("the reference and candidate share no frame time");
  const auto [lo, hi] = std::minmax_element(paired_ref.begin(), paired_ref.end());
  return *hi - *lo > 0 ? *hi - *lo : 1.0;
}

}  // namespace

namespace {

// The frame_N.png of an earlier run into the same directory that this run did not draw: removed,
// so that the directory holds this run's frames only, all listed in its frames.json.
void RemoveStaleFrames(const std::filesystem::path& out_dir,
                       const std::vector<std::size_t>& frames) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(out_dir, error)) {
    const std::string name = entry.path().filename().string();
    const std::string digits = name.size() > 10 ? name.substr(6, name.size() - 10) : "";
    if (name.rfind("frame_", 0) != 0 || name.substr(name.size() - 4) != ".png" || digits.empty() ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      continue;
    const bool drawn = std::any_of(frames.begin(), frames.end(),
                                   [&](std::size_t fr) { return std::to_string(fr) == digits; });
    if (!drawn) std::filesystem::remove(entry.path(), error);
  }
}

}  // namespace

nlohmann::json RenderFrames(FrameSource& refs, FrameSource& cands,
                            const std::vector<std::size_t>& frames, const RenderOptions& o,
                            const std::filesystem::path& out_dir) {
  CheckSize(o);
  RenderOptions options = o;
  if (!options.tracking) options.tracking = Track{};
  const Track& track = *options.tracking;
  const Trajectory& ref = refs.header();
  const auto pairs = PairFramesByTime(ref, cands.header());
  // Every frame is checked before any is drawn or any directory created: one picture a frame.
  if (frames.empty()) throw InputError("no frame to render: expected at least one frame index");
  std::vector<std::size_t> partners;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::size_t fr = frames[k];
    if (std::find(frames.begin(), frames.begin() + k, fr) != frames.begin() + k)
      throw InputError("frame " + std::to_string(fr) + " is listed twice");
    const auto it =
        std::find_if(pairs.begin(), pairs.end(), [fr](auto p) { return p.first == fr; });
    if (it == pairs.end())
      throw InputError("frame " + std::to_string(fr) + " has no candidate frame at the same time" +
                       " (the reference has " + std::to_string(ref.frame_count()) + " frames)");
    partners.push_back(it->second);
  }
  const double scale = PairedRange(refs, pairs, track);
  SideBySideFrame compose(refs.Frame(0), options);
  nlohmann::json entries = nlohmann::json::array();
  MissingDirectories created(out_dir);  // a failure leaves no empty folder it made
  CreateOutputDirectories(
      out_dir);         // InputError naming out_dir and why, not a raw filesystem_error
  OutputGroup written;  // the PNGs and frames.json appear together (a rerun never mixes)
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::size_t fr = frames[k], fc = partners[k];
    const FrameRef a = refs.Frame(fr), b = cands.Frame(fc);
    const double vr = track.ValueAt(a.trajectory, a.frame),
                 vc = track.ValueAt(b.trajectory, b.frame);
    auto& rgba = compose.Compose(a, b);
    Title(compose.text(), rgba, options);
    const std::string diff = Format("diff %+.4f cu", vc - vr) +
                             Format(" (%.2f%% of range)", 100 * std::abs(vc - vr) / scale);
    compose.text().Draw(rgba, o.width, o.height, compose.panel() + 12, Row(options, 3), diff, 16,
                        kTextColour);
    const std::string name = "frame_" + std::to_string(fr) + ".png";
    WritePng(written.Stage(out_dir / name), rgba, o.width, o.height);
    entries.push_back({{"image", name},
                       {"reference_frame", fr},
                       {"candidate_frame", fc},
                       {"time_s", ref.time_s[fr]},
                       {"reference_value", vr},
                       {"candidate_value", vc},
                       {"difference", vc - vr},
                       {"relative_difference", std::abs(vc - vr) / scale}});
  }
  const nlohmann::json result = {{"track", track.ToJson()},
                                 {"reference_label", o.reference_label},
                                 {"candidate_label", o.candidate_label},
                                 {"reference_range_cu", scale},
                                 {"frames", entries}};
  WriteFileAtomically(written.Stage(out_dir / "frames.json"), result.dump(2) + "\n");
  written.Commit();
  created.Keep();
  RemoveStaleFrames(out_dir, frames);
  return result;
}

nlohmann::json RenderFrames(const Trajectory& ref, const Trajectory& cand,
                            const std::vector<std::size_t>& frames, const RenderOptions& o,
                            const std::filesystem::path& out_dir) {
  const auto refs = MemoryFrameSource(ref), cands = MemoryFrameSource(cand);
  return RenderFrames(*refs, *cands, frames, o, out_dir);
}

nlohmann::json VideoSummary::ToJson(const std::filesystem::path& output) const {
  return {{"output", output.string()},
          {"frames", frames},
          {"width", width},
          {"height", height},
          {"fps", fps},
          {"duration_s", duration_s},
          {"notes", notes}};
}

std::string VideoSummary::ToText(const std::filesystem::path& output) const {
  return "wrote " + output.string() + ": " + std::to_string(frames) + " frames " +
         std::to_string(width) + "x" + std::to_string(height) + " at " + std::to_string(fps) +
         " fps";
}

void ParseFrameSize(const std::string& text, RenderOptions* options) {
  // Two runs of at most 5 digits (CheckSize allows 16 to 8192): sscanf's %d on a longer one is
  // undefined.
  const std::size_t x = text.find('x');
  const auto digits = [](std::string_view s) {
    return !s.empty() && s.size() <= 5 && s.find_first_not_of("0123456789") == s.npos;
  };
  if (x == std::string::npos || !digits(std::string_view(text).substr(0, x)) ||
      !digits(std::string_view(text).substr(x + 1)))
    throw InputError("--size " + OneLine(text, 40) + ": expected WIDTHxHEIGHT, e.g. 1280x720");
  options->width = std::stoi(text.substr(0, x));
  options->height = std::stoi(text.substr(x + 1));
}

std::string PanelLabel(const std::filesystem::path& trajectory, const std::string& fallback) {
  std::filesystem::path stem = trajectory;
  while (stem.has_extension()) stem = stem.stem();
  const std::string name = stem.filename().string();
  if (name == "position_buffer" || name == "trajectory") {
    const std::string folder = trajectory.parent_path().filename().string();
    return folder.empty() ? fallback : folder;
  }
  return name.empty() ? fallback : name;
}

}  // namespace owval::render
