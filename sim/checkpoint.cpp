// Simulation::saveCheckpoint / loadCheckpoint. The file is the exact state, so that a resumed run
// is bit-identical to an uninterrupted one; it ends with an xxHash of every byte before it, and a
// load checks that, then every count and length against the bytes left, before allocating.
// Layout (native byte order, as written):
//   "MFCKPT" + 2 digits format version | u64 scene simulationHash | i32 frame | f64 time | u64 nextId
//   | u32 sizeof(SimulationCounters), the counters | u32 phase count, per phase u64 left the domain,
//   u64 born | u32 attribute mask | u64 particle count n
//   | per array (ParticleSet::forEachArray order): u32 name length, name, u32 element size, n elements
//   | u32 effect count | per effect: u32 name length, name, u64 state bytes, state
//   | u64 XXH3_64bits of all of the above
#include <fmt/format.h>
#include <xxhash.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <type_traits>

#include "file_util.h"
#include "simulation.h"

namespace mf {

namespace {

constexpr char kTag[6] = {'M', 'F', 'C', 'K', 'P', 'T'};
constexpr int kFormatVersion = 4;  // 03: no per-phase domain and birth counts  // 02: no checksum, no counters size
constexpr size_t kChecksumBytes = sizeof(uint64_t);
constexpr const char* kDelete = "; delete it to simulate from the start";

static_assert(std::is_trivially_copyable_v<SimulationCounters>, "counters are stored as raw bytes");

template <class T>
void put(std::string& o, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  o.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
void putName(std::string& o, const char* name) {
  put(o, uint32_t(std::strlen(name)));
  o.append(name);
}

// Reads the checksummed body; every read is checked against the bytes left, so a count can
// never make it read past the end or allocate more than the file holds.
class Reader {
 public:
  Reader(const std::string& path, std::string_view body) : path_(path), body_(body) {}
  [[noreturn]] void fail(const std::string& why) const { throw std::runtime_error(path_ + ": " + why + kDelete); }
  uint64_t left() const { return body_.size() - at_; }
  std::string_view take(uint64_t n, const char* what) {
    if (n > left())
      fail(fmt::format("checkpoint layout differs ({} needs {} bytes, {} left): not written by this version of multifluid",
                       what, n, left()));
    const std::string_view v = body_.substr(at_, size_t(n));
    at_ += size_t(n);
    return v;
  }
  template <class T>
  T get(const char* what) {
    T v;
    std::memcpy(&v, take(sizeof(T), what).data(), sizeof(T));
    return v;
  }
  std::string_view name(const char* what) {
    const uint32_t len = get<uint32_t>(what);
    if (len > 64) fail(fmt::format("checkpoint layout differs ({} is {} bytes long)", what, len));
    return take(len, what);
  }

 private:
  const std::string& path_;
  std::string_view body_;
  size_t at_ = 0;
};

template <class T>
bool allFinite(const std::vector<T>& v) {
  if constexpr (std::is_same_v<T, Real>) {
    for (Real x : v)
      if (!std::isfinite(x)) return false;
  } else if constexpr (std::is_same_v<T, Vec3>) {
    for (const Vec3& x : v)
      if (!isFinite(x)) return false;
  }
  return true;
}

}  // namespace

void Simulation::saveCheckpoint(const std::string& path, int frame) const {
  std::string o;
  o.append(kTag, sizeof kTag);
  o.append(fmt::format("{:02d}", kFormatVersion));
  put(o, scene_.simulationHash);
  put(o, int32_t(frame));
  put(o, time_);
  put(o, nextId_);
  put(o, uint32_t(sizeof(SimulationCounters)));
  put(o, counters_);
  put(o, uint32_t(leftDomain_.size()));
  for (size_t p = 0; p < leftDomain_.size(); ++p) put(o, leftDomain_[p]), put(o, bornByPhase_[p]);
  put(o, ps_.attributes);
  put(o, uint64_t(ps_.size()));
  const_cast<ParticleSet&>(ps_).forEachArray([&](const char* name, const auto& v) {
    putName(o, name);
    put(o, uint32_t(sizeof(v[0])));
    o.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
  });
  // State the effects keep outside the particles (emitter counters, heat exchangers).
  put(o, uint32_t(effects_.size()));
  for (const auto& e : effects_) {
    const std::vector<uint8_t> state = e->saveState();
    putName(o, e->name());
    put(o, uint64_t(state.size()));
    o.append(reinterpret_cast<const char*>(state.data()), state.size());
  }
  put(o, uint64_t(XXH3_64bits(o.data(), o.size())));
  writeFileAtomically(path, o);
}

int Simulation::loadCheckpoint(const std::string& path) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(path + ": " + why + kDelete); };

  // The largest checkpoint this scene could have written: every array for 8 times the particles
  // of a lattice filling the domain at the particle spacing (the watchdog keeps the fluid far
  // below 8 times its rest density), plus what was seeded (blocks may reach outside the domain)
  // and room for small domains and the effects' state. Checked before a byte is read, so that a
  // wrong path to a huge file is refused rather than read into memory.
  size_t bytesPerParticle = 0;
  ps_.forEachArray([&](const char*, const auto& v) { bytesPerParticle += sizeof(v[0]); });
  const Vec3 extent = scene_.domainMax - scene_.domainMin;
  const double s = scene_.solver.particleSpacing;
  const double latticeParticles = (extent.x / s + 1) * (extent.y / s + 1) * (extent.z / s + 1);
  const double maxParticles = std::min(8 * latticeParticles + double(ps_.size()) + double(1 << 20), 4294967295.0);
  const double maxBytes = maxParticles * double(bytesPerParticle) + double(1 << 20);

  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw std::runtime_error(path + ": cannot read checkpoint (" + ec.message() + ")");
  if (double(size) > maxBytes)
    fail(fmt::format("{} bytes, more than a checkpoint of this scene can hold ({:.0f}): not a checkpoint of this scene", size,
                     maxBytes));
  std::string bytes(size_t(size), '\0');
  {
    std::ifstream in(path, std::ios::binary);
    if (!in.read(bytes.data(), std::streamsize(bytes.size())) || in.peek() != std::char_traits<char>::eof())
      throw std::runtime_error(path + ": cannot read checkpoint (read error, or the file changed while being read)");
  }

  const size_t headerBytes = sizeof kTag + 2;
  if (bytes.size() < headerBytes + kChecksumBytes)
    fail(fmt::format("only {} bytes: not a multifluid checkpoint, or one cut short", bytes.size()));
  if (std::memcmp(bytes.data(), kTag, sizeof kTag) != 0) fail("not a multifluid checkpoint (no MFCKPT tag at the start)");
  const std::string version = bytes.substr(sizeof kTag, 2);
  if (version != fmt::format("{:02d}", kFormatVersion))
    fail(fmt::format("checkpoint format \"{}\", written by another version of multifluid (this one reads {:02d})", version,
                     kFormatVersion));
  // The checksum first: nothing is read from a damaged file.
  const size_t bodyEnd = bytes.size() - kChecksumBytes;
  uint64_t stored;
  std::memcpy(&stored, bytes.data() + bodyEnd, kChecksumBytes);
  if (XXH3_64bits(bytes.data(), bodyEnd) != stored) fail("checksum mismatch, the file is damaged (or was cut short)");

  Reader in(path, std::string_view(bytes).substr(headerBytes, bodyEnd - headerBytes));
  if (in.get<uint64_t>("scene hash") != scene_.simulationHash)
    throw std::runtime_error(path + ": checkpoint was made from a different scene (or other --set values); use that scene, or " +
                             "delete it to simulate from the start");
  const int32_t frame = in.get<int32_t>("frame");
  if (frame < 0 || frame > scene_.lastFrame())
    in.fail(fmt::format("frame {} is outside this scene's frames 0..{}", frame, scene_.lastFrame()));
  const Real time = in.get<Real>("time");
  if (!std::isfinite(time) || time < 0 || time > scene_.endTime * (1 + 1e-9))
    in.fail(fmt::format("time {} s is not in this scene's 0..{} s", time, scene_.endTime));
  const uint64_t nextId = in.get<uint64_t>("next id");
  if (in.get<uint32_t>("counters size") != sizeof(SimulationCounters)) in.fail("checkpoint layout differs (counters)");
  const SimulationCounters counters = in.get<SimulationCounters>("counters");
  if (in.get<uint32_t>("phase count") != scene_.phases.size()) in.fail("checkpoint layout differs (phases)");
  std::vector<uint64_t> leftDomain(scene_.phases.size()), born(scene_.phases.size());
  for (size_t p = 0; p < leftDomain.size(); ++p) leftDomain[p] = in.get<uint64_t>("left the domain"), born[p] = in.get<uint64_t>("born");
  ParticleSet loaded;
  loaded.attributes = in.get<AttributeMask>("attribute mask");
  if (loaded.attributes != ps_.attributes)
    in.fail(fmt::format("checkpoint layout differs (attributes {:#x}, this scene's effects use {:#x})", loaded.attributes,
                        ps_.attributes));
  const uint64_t n = in.get<uint64_t>("particle count");
  if (n > bytes.size() / bytesPerParticle || n > UINT32_MAX)
    in.fail(fmt::format("particle count {} is more than the file's {} bytes can hold", n, bytes.size()));
  loaded.forEachArray([&](const char* name, auto& v) {
    if (in.name("array name") != name || in.get<uint32_t>("element size") != sizeof(v[0]))
      in.fail(fmt::format("checkpoint layout differs (array \"{}\")", name));
    const std::string_view data = in.take(n * sizeof(v[0]), name);  // checked before resize
    v.resize(size_t(n));
    std::memcpy(static_cast<void*>(v.data()), data.data(), data.size());
    // The solver never keeps a non-finite value (the watchdog), so one here was put in from outside.
    if (!allFinite(v)) in.fail(fmt::format("array \"{}\" holds a non-finite value", name));
  });
  for (size_t i = 0; i < n; ++i) {
    if (loaded.phase[i] >= scene_.phases.size() || loaded.id[i] >= nextId || !(loaded.mass[i] > 0) ||
        !(loaded.restDensity[i] > 0))
      in.fail(fmt::format("particle {} is invalid (phase {} of {}, id {} of {}, mass {}, rest density {})", i, loaded.phase[i],
                          scene_.phases.size(), loaded.id[i], nextId, loaded.mass[i], loaded.restDensity[i]));
  }
  if (in.get<uint32_t>("effect count") != effects_.size()) in.fail("checkpoint layout differs (effects)");
  std::vector<std::vector<uint8_t>> states;
  for (const auto& e : effects_) {
    const std::string_view name = in.name("effect name");
    const uint64_t stateBytes = in.get<uint64_t>("effect state size");
    // Effects keep a fixed-size state for a given scene: a size check now means loadState
    // below cannot fail half-way, after other state was replaced.
    if (name != e->name() || stateBytes != e->saveState().size())
      in.fail(fmt::format("checkpoint layout differs (effect \"{}\", {} bytes)", name, stateBytes));
    const std::string_view state = in.take(stateBytes, e->name());
    states.emplace_back(state.begin(), state.end());
  }
  if (in.left() != 0) in.fail(fmt::format("checkpoint layout differs ({} bytes after the last effect)", in.left()));

  // Everything was checked: only now is the simulation's state replaced.
  ps_ = std::move(loaded);
  time_ = time;
  nextId_ = nextId;
  counters_ = counters;
  leftDomain_ = leftDomain, bornByPhase_ = born;
  for (size_t k = 0; k < effects_.size(); ++k) effects_[k]->loadState(states[k]);
  searchAndDensity();
  return frame;
}

}  // namespace mf
