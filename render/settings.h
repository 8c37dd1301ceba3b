// The render stage's settings: the [render] table of a scene file (image, samples, camera, sky,
// light, table) and the materials and props it draws. Read by settings_file.cpp.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/scene.h"
#include "surfacing/settings.h"

namespace mf {

/// A colour ramp over a particle attribute that surfacing writes as a grid ("temperature" or
/// "dye"): evenly spaced colours from lo to hi, linear between them, held beyond.
struct ColourRamp {
  std::string attribute;  // empty: no ramp
  Real lo = 0, hi = 1;
  std::vector<Vec3> colours;  // at least 2
  bool empty() const { return attribute.empty(); }
  Vec3 at(Real v) const {
    const Real s = std::clamp((v - lo) / (hi - lo), Real(0), Real(1)) * Real(colours.size() - 1);
    const size_t k = std::min(size_t(s), colours.size() - 2);
    const Real f = s - Real(k);
    return colours[k] * (1 - f) + colours[k + 1] * f;
  }
};

/// How a phase or a solid looks (read by render/). Units: coefficients per metre, radiance
/// relative (1 = a white sky's brightness).
struct MaterialSpec {
  enum class Kind {
    Dielectric,  // clear: Fresnel reflection and refraction, Beer-Lambert absorption inside
    Medium,      // translucent: a dielectric boundary around a scattering medium (wax)
    Diffuse,     // opaque Lambertian
    Emitter,     // opaque, glowing
  };
  Kind kind = Kind::Dielectric;
  Real ior = 1.33;
  Vec3 absorption;            // sigma_a per RGB channel, 1/m
  Real scattering = 0;        // sigma_s, 1/m (Medium), isotropic
  Vec3 colour{0.8, 0.8, 0.8}; // Diffuse albedo
  Vec3 emission;              // Emitter radiance; for a Medium, radiance emitted per metre
  int priority = 10;          // nested dielectrics: where volumes overlap, the higher one wins
  // Inside the volume, absorption and emission from the fluid's attribute grid, in place of
  // the constants above (phases only; surfacing.attributes must write the attribute).
  ColourRamp absorptionRamp, emissionRamp;
  Real thickness = 0.004;     // solids: wall thickness, m (glass)
  bool visible = true;        // solids: drawn at all
};

/// A camera pose at a time ([[render.camera_key]]); render/camera.h interpolates them.
struct CameraKey {
  Real time = 0;  // s
  Vec3 position, lookAt;
  Real fov = 40;  // vertical, degrees
};

/// An object only the render stage sees ([[render.prop]]: a lamp's base and cap): a solid's
/// shape, drawn as a shell of the material's thickness around it, opaque and diffuse by default.
struct PropSpec {
  SolidSpec shape;
  MaterialSpec material;
};

/// The render stage's camera, lights and materials.
struct RenderSettings {
  int width = 480, height = 270;
  int samples = 16;                 // paths per pixel
  int maxDepth = 16;                // bounces per path
  Real indirectClamp = 1;           // cap on light arriving after a diffuse bounce (0: none)
  Real regularise = 0;              // degrees: mirrors after a diffuse vertex blurred by this cone (0: off)
  Real shutter = 0;                 // motion blur: the shutter's open time, a fraction of the frame interval, centred on the frame (0: off)
  bool sobol = true;                // Owen-scrambled Sobol samples (false: independent random ones)
  Real adaptive = 0.5;              // share of the samples placed by a first pass's noise (0: every pixel the same)
  bool mis = true;                  // light samples and lobe samples weighted by the power heuristic
  bool animatedSeed = false;        // the frame in the sampler's seed (noise changes every frame)
  bool denoise = true;              // the shipped frame filtered by render/denoise.h (the noisy one kept in the EXR)
  int denoiseIterations = 5;        // its à-trous passes (the filter spans 4 (2^n - 1) + 1 pixels)
  std::vector<uint16_t> phases;     // phases drawn (from their level sets); default: the surfaced ones
  Vec3 cameraPosition{0.5, 0.5, 2.0}, lookAt{0.5, 0.3, 0.0};
  Real fov = 40;                    // vertical, degrees
  std::string cameraFraming;        // without camera keys: what the camera was set to frame
  std::vector<CameraKey> cameraKeys;  // a moving camera, times increasing (empty: the one above)
  Vec3 skyZenith{0.35, 0.45, 0.65}, skyHorizon{1.0, 1.0, 1.0};
  Vec3 skyGround{0.25, 0.25, 0.25}; // radiance from below the horizon
  Vec3 lightPosition;               // a spherical area light
  Real lightRadius = 0;             // m; 0: no light but the sky
  Vec3 lightEmission{20, 19, 17};
  bool floor = true;                // a table top at floorHeight (default: under the lowest solid)
  Real floorHeight = 0;
  Real checkerSize = 0.05;          // m; 0: plain
  std::vector<MaterialSpec> phaseMaterials;  // one per phase
  std::vector<MaterialSpec> solidMaterials;  // one per solid
  std::vector<PropSpec> props;
};

namespace scene_reading {
struct SceneDocument;
}

/// The [render] table of a scene file, after its simulation and surfacing parts (it names phases
/// and solids, and reads the grids surfacing writes); every problem goes to doc.reader
/// (sim/scene_reader.h). Without [render], every phase and solid gets a default look by what the
/// scene's effects make of it, and the camera frames the solids.
RenderSettings readRenderSettings(scene_reading::SceneDocument& doc, const Scene& scene, const SurfacingSettings& surfacing);

}  // namespace mf
