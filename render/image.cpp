#include "image.h"

#include "sim/file_util.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <Imath/half.h>

namespace fs = std::filesystem;

namespace mf::render {

float linearToSrgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

}  // namespace

namespace {

/// Encodes with OpenImageIO in memory, then writes by writeFileAtomically: every write, the flush
/// and the close are checked there, so a full disk never leaves a truncated image under its
/// final name.
void encodeAndWrite(const std::string& path, const OIIO::ImageSpec& spec, const void* pixels, OIIO::TypeDesc format) {
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error("cannot write " + path + ": " + OIIO::geterror());
  if (!out->supports("ioproxy") || !out->set_ioproxy(&memory))
    throw std::runtime_error("cannot write " + path + ": the " + lowerExtension(path) + " writer cannot encode to memory");
  bool ok = out->open(path, spec) && out->write_image(format, pixels);
  const std::string error = out->geterror();
  ok = out->close() && ok;
  if (!ok || encoded.empty()) throw std::runtime_error("cannot encode " + path + ": " + error);
  writeFileAtomically(path, std::string(encoded.begin(), encoded.end()));
}

void exrAttributes(OIIO::ImageSpec& spec) {
  spec.attribute("oiio:ColorSpace", "Linear");
  spec.attribute("compression", "zip");
  spec.attribute("DateTime", "");  // else the current time: equal images must give equal files
}

}  // namespace

void writeImage(const std::string& path, const Image& image) {
  const size_t n = size_t(image.width) * image.height * 3;
  if (lowerExtension(path) == ".png") {
    std::vector<unsigned char> bytes(n);
    for (size_t i = 0; i < n; ++i) bytes[i] = (unsigned char)std::lround(255.0f * linearToSrgb(image.rgb[i]));
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    encodeAndWrite(path, spec, bytes.data(), OIIO::TypeDesc::UINT8);
  } else {
    // Half floats: what compositors expect of beauty passes, and half the size.
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::HALF);
    exrAttributes(spec);
    encodeAndWrite(path, spec, image.rgb.data(), OIIO::TypeDesc::FLOAT);
  }
}

void writeExrChannels(const std::string& path, int width, int height, const std::vector<std::string>& names,
                      const std::vector<float>& data, const std::vector<bool>& fullFloat) {
  const int channels = int(names.size());
  if (data.size() != size_t(width) * height * channels || fullFloat.size() != names.size())
    throw std::logic_error("writeExrChannels: " + path + ": data and channel names disagree");
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::HALF);
  spec.channelnames = names;
  spec.channelformats.clear();
  for (int c = 0; c < channels; ++c) spec.channelformats.push_back(fullFloat[c] ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF);
  for (int c = 0; c < channels; ++c)
    if (names[c] == "Z") spec.z_channel = c;
  exrAttributes(spec);
  encodeAndWrite(path, spec, data.data(), OIIO::TypeDesc::FLOAT);
}

Image readImage(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw std::runtime_error("cannot read image " + path + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels < 3) throw std::runtime_error(path + ": expected an RGB image");
  // The beauty by name where the file has R, G and B (a multi-layer frame keeps AOVs beside it,
  // in an order of the format's choosing); else the first three channels.
  int rgb[3] = {0, 1, 2};
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    const int at = spec.channelindex(names[c]);
    if (at < 0) {
      rgb[0] = 0, rgb[1] = 1, rgb[2] = 2;
      break;
    }
    rgb[c] = at;
  }
  Image image(spec.width, spec.height);
  std::vector<float> all(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
    throw std::runtime_error("cannot read image " + path + ": " + in->geterror());
  const bool srgb = spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16;
  for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
    for (int c = 0; c < 3; ++c) {
      const float v = all[p * spec.nchannels + rgb[c]];
      image.rgb[p * 3 + c] = srgb ? srgbToLinear(v) : v;
    }
  in->close();
  return image;
}

ImageDiff compareImages(const Image& a, const Image& b, double failThreshold, Image* difference) {
  ImageDiff d;
  if (a.width != b.width || a.height != b.height) {
    d.sizeMismatch = true;
    return d;
  }
  d.pixels = size_t(a.width) * a.height;
  if (difference) *difference = Image(a.width, a.height);
  double sum = 0, sum2 = 0;
  for (size_t p = 0; p < d.pixels; ++p) {
    double worst = 0;
    for (int c = 0; c < 3; ++c) {
      const double e = std::abs(double(linearToSrgb(a.rgb[p * 3 + c])) - linearToSrgb(b.rgb[p * 3 + c]));
      worst = std::max(worst, e);
      sum += e;
      sum2 += e * e;
      if (difference) difference->rgb[p * 3 + c] = float(e);
    }
    d.maxError = std::max(d.maxError, worst);
    if (worst > failThreshold) ++d.failedPixels;
  }
  d.meanError = sum / (3.0 * d.pixels);
  d.rmsError = std::sqrt(sum2 / (3.0 * d.pixels));
  return d;
}

}  // namespace mf::render
