#include "preview.h"

#include <GL/osmesa.h>
#include <GL/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "camera.h"
#include "image.h"
#include "sim/particle_io.h"

namespace fs = std::filesystem;

namespace mf::render {

namespace {

/// A unit sphere as triangles (latitude-longitude), drawn with glDrawArrays.
void unitSphere(std::vector<float>& vertices, int stacks = 8, int slices = 12) {
  auto at = [&](int i, int j) {
    const double th = M_PI * i / stacks, ph = 2 * M_PI * j / slices;
    return Vec3{std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)};
  };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const Vec3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      for (const Vec3& p : {a, b, c, a, c, d}) vertices.insert(vertices.end(), {float(p.x), float(p.y), float(p.z)});
    }
}

/// A display colour for a phase from its render material: what white light looks like after
/// a few centimetres of it.
Vec3 phaseColour(const MaterialSpec& m) {
  switch (m.kind) {
    case MaterialSpec::Kind::Diffuse:
      return m.colour;
    case MaterialSpec::Kind::Emitter: {
      const Real e = std::max({m.emission.x, m.emission.y, m.emission.z, 1e-9});
      return m.emission / e;
    }
    default: {
      const Vec3 c{std::exp(-0.05 * m.absorption.x), std::exp(-0.05 * m.absorption.y), std::exp(-0.05 * m.absorption.z)};
      return m.ior <= 1.0 ? Vec3{0.9, 0.9, 0.95} : c * 0.85 + Vec3{0.1, 0.1, 0.1};
    }
  }
}

Vec3 heatColour(double t) {  // blue -> cyan -> yellow -> red
  t = std::clamp(t, 0.0, 1.0);
  if (t < 1.0 / 3) return {0.1, 0.2 + 2.1 * t, 1.0};
  if (t < 2.0 / 3) return {3 * (t - 1.0 / 3), 0.9, 1.0 - 3 * (t - 1.0 / 3)};
  return {1.0, 0.9 - 2.7 * (t - 2.0 / 3), 0.0};
}

}  // namespace

PreviewResult renderPreview(const std::string& particleFile, const Scene& scene, const RenderSettings& settings, const std::string& pngPath,
                            PreviewColour colour, double tMin, double tMax) {
  PreviewResult result;
  if (fs::exists(pngPath)) {
    result.skipped = true;
    return result;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const ParticleFrame frame = readParticleFrame(particleFile);
  checkFrameMatchesScene(particleFile, frame.info, scene);
  const RenderSettings rs = atTime(settings, frame.info.time);
  const int w = rs.width, h = rs.height;
  OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!ctx) throw std::runtime_error("OSMesa: cannot create an off-screen context");
  std::vector<unsigned char> pixels(size_t(w) * h * 4);
  if (!OSMesaMakeCurrent(ctx, pixels.data(), GL_UNSIGNED_BYTE, w, h)) {
    OSMesaDestroyContext(ctx);
    throw std::runtime_error("OSMesa: cannot make the context current");
  }
  glViewport(0, 0, w, h);
  glClearColor(float(rs.skyHorizon.x * 0.8), float(rs.skyHorizon.y * 0.8), float(rs.skyHorizon.z * 0.8), 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  // Projection and view from the render camera, so previews frame like final images.
  const double nearZ = 0.01, farZ = 100;
  const double top = nearZ * std::tan(0.5 * rs.fov * M_PI / 180), right = top * w / h;
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glFrustum(-right, right, -top, top, nearZ, farZ);
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  const Vec3 f = normalize(rs.lookAt - rs.cameraPosition);
  Vec3 s = normalize(cross(f, Vec3{0, 1, 0}));
  if (lengthSquared(s) == 0) s = {1, 0, 0};
  const Vec3 u = cross(s, f);
  const double view[16] = {s.x, u.x, -f.x, 0, s.y, u.y, -f.y, 0, s.z, u.z, -f.z, 0, 0, 0, 0, 1};
  glMultMatrixd(view);
  glTranslated(-rs.cameraPosition.x, -rs.cameraPosition.y, -rs.cameraPosition.z);
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT0);
  const Vec3 lightDir = rs.lightRadius > 0 ? normalize(rs.lightPosition - rs.lookAt) : normalize(Vec3{0.4, 1, 0.6});
  const float lightPos[4] = {float(lightDir.x), float(lightDir.y), float(lightDir.z), 0};
  const float ambient[4] = {0.35f, 0.35f, 0.35f, 1}, diffuse[4] = {0.75f, 0.75f, 0.75f, 1};
  glLightfv(GL_LIGHT0, GL_POSITION, lightPos);
  glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
  glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
  glEnable(GL_COLOR_MATERIAL);
  glColorMaterial(GL_FRONT, GL_AMBIENT_AND_DIFFUSE);
  glEnable(GL_NORMALIZE);

  std::vector<float> sphere;
  unitSphere(sphere);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);
  glVertexPointer(3, GL_FLOAT, 0, sphere.data());
  glNormalPointer(GL_FLOAT, 0, sphere.data());  // a unit sphere's normal is its position
  const GLsizei count = GLsizei(sphere.size() / 3);

  std::vector<Vec3> colours;
  for (size_t p = 0; p < scene.phases.size(); ++p) colours.push_back(phaseColour(settings.phaseMaterials[p]));
  auto temperature = frame.scalars.find("temperature");
  const bool byTemperature = colour == PreviewColour::Temperature && temperature != frame.scalars.end();
  for (size_t i = 0; i < frame.size(); ++i) {
    const int phase = frame.phase[i];
    const Vec3 c = byTemperature ? heatColour((temperature->second[i] - tMin) / std::max(1e-9, tMax - tMin))
                                 : (phase >= 0 && size_t(phase) < colours.size() ? colours[phase] : Vec3{0.7, 0.7, 0.7});
    glColor3d(c.x, c.y, c.z);
    glPushMatrix();
    glTranslated(frame.position[i].x, frame.position[i].y, frame.position[i].z);
    const double r = frame.pscale[i];
    glScaled(r, r, r);
    glDrawArrays(GL_TRIANGLES, 0, count);
    glPopMatrix();
  }
  glFinish();
  OSMesaDestroyContext(ctx);

  Image image(w, h);  // OpenGL rows start at the bottom
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = &pixels[(size_t(h - 1 - y) * w + x) * 4];
      image.set(x, y, {srgbToLinear(p[0] / 255.0f), srgbToLinear(p[1] / 255.0f), srgbToLinear(p[2] / 255.0f)});
    }
  fs::create_directories(fs::path(pngPath).parent_path());
  writeImage(pngPath, image);
  result.particles = frame.size();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace mf::render
