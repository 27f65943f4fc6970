#include "tsuchi/io/checkpoint.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/appended_file.hpp"
#include "tsuchi/io/atomic_file.hpp"
#include "tsuchi/io/toml_section.hpp"
#include "tsuchi/model/material_state.hpp"

#include <fmt/format.h>

#include <sys/stat.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <memory>
#include <cmath>
#include <cstring>
#include <map>
#include <type_traits>

namespace tsuchi {

static_assert(std::endian::native == std::endian::little, "checkpoints are written little-endian");

namespace {

constexpr char magic[8] = {'T', 'S', 'U', 'C', 'H', 'I', 'C', 'K'};
constexpr std::size_t header_size = 8 + 4 + 4 + 8 + 8;  // magic, version, dimension, fingerprint, particles

std::uint32_t crc32_of(std::string_view bytes) { return crc32_update(0, bytes); }

// Numbers, or fixed-size Eigen vectors that are nothing but their coefficients: safe to copy as
// bytes (Eigen's types are not formally trivially copyable).
template <class T>
constexpr bool is_plain() {
  if constexpr (std::is_arithmetic_v<T>) return true;
  else return T::SizeAtCompileTime > 0 && sizeof(T) == T::SizeAtCompileTime * sizeof(typename T::Scalar);
}

class Encoder {
 public:
  template <class T>
  void raw(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  // A section: name length (u32), name, byte count (u64), bytes.
  void section(std::string_view name, const void* data, std::size_t bytes) {
    raw(static_cast<std::uint32_t>(name.size()));
    out_.append(name);
    raw(static_cast<std::uint64_t>(bytes));
    out_.append(static_cast<const char*>(data), bytes);
  }
  template <class T>
  void array(std::string_view name, const std::vector<T>& a) {
    static_assert(is_plain<T>());
    section(name, a.data(), a.size() * sizeof(T));
  }
  template <class T>
  void scalar(std::string_view name, const T& v) {
    section(name, &v, sizeof(T));
  }
  void text(std::string_view name, std::string_view s) { section(name, s.data(), s.size()); }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

[[noreturn]] void refuse(const std::string& source, const std::string& what) {
  throw InputError(fmt::format("{}: not a usable checkpoint: {}", source, what));
}

// Splits the sections once, then hands each out by name with its size checked, so a damaged or
// hostile file can only ever produce an error.
class Decoder {
 public:
  Decoder(std::string_view body, const std::string& source) : source_(source) {
    std::size_t at = 0;
    auto take = [&](std::size_t n, const char* what) {
      if (body.size() - at < n) fail(fmt::format("truncated in {}", what));
      const std::string_view s = body.substr(at, n);
      at += n;
      return s;
    };
    while (at < body.size()) {
      std::uint32_t name_len = 0;
      std::memcpy(&name_len, take(4, "a section name").data(), 4);
      if (name_len == 0 || name_len > 64) fail("a section name has an impossible length");
      const std::string name(take(name_len, "a section name"));
      std::uint64_t n = 0;
      std::memcpy(&n, take(8, "a section size").data(), 8);
      if (n > body.size() - at) fail(fmt::format("section \"{}\" is longer than the file", name));
      if (!sections_.emplace(name, take(static_cast<std::size_t>(n), "a section")).second)
        fail(fmt::format("section \"{}\" appears twice", name));
    }
  }

  std::string_view section(const std::string& name) const {
    const auto it = sections_.find(name);
    if (it == sections_.end()) fail(fmt::format("section \"{}\" is missing", name));
    return it->second;
  }
  template <class T>
  void array(const std::string& name, std::vector<T>& a, std::size_t count) const {
    static_assert(is_plain<T>());
    const std::string_view s = section(name);
    if (s.size() != count * sizeof(T))
      fail(fmt::format("section \"{}\" holds {} bytes, expected {} ({} particles)", name, s.size(),
                       count * sizeof(T), count));
    a.resize(count);
    if (count > 0) std::memcpy(static_cast<void*>(a.data()), s.data(), s.size());
  }
  template <class T>
  T scalar(const std::string& name) const {
    const std::string_view s = section(name);
    if (s.size() != sizeof(T)) fail(fmt::format("section \"{}\" has the wrong size", name));
    T v;
    std::memcpy(&v, s.data(), sizeof(T));
    return v;
  }
  std::string text(const std::string& name) const { return std::string(section(name)); }
  bool has(const std::string& name) const { return sections_.find(name) != sections_.end(); }

  [[noreturn]] void fail(const std::string& what) const { refuse(source_, what); }

 private:
  std::string source_;
  std::map<std::string, std::string_view, std::less<>> sections_;
};

// Every array of real numbers, whichever fields Particles has; integer arrays are checked below.
template <int D>
bool all_finite(const Particles<D>& p) {
  bool finite = true;
  p.for_each_array([&](const char*, const auto& a) {
    using T = typename std::decay_t<decltype(a)>::value_type;
    if constexpr (std::is_floating_point_v<T>) {
      for (const double v : a) finite = finite && std::isfinite(v);
    } else if constexpr (!std::is_integral_v<T>) {
      for (const auto& v : a) finite = finite && v.allFinite();
    }
  });
  return finite;
}

// The particle state must make sense for the model it is loaded into; the checksum guards against
// damage, this against a file that was never written by tsuchi.
template <int D>
void check_particles(const Particles<D>& p, const Model<D>& model, const Decoder& in) {
  const std::size_t n = p.size();
  const auto nbodies = static_cast<std::int32_t>(model.body_names.size());
  const auto nmat = static_cast<std::int32_t>(model.materials.size());
  if (!all_finite(p)) in.fail("a particle value is not finite");
  // A staged run's ids: 0..id_count-1 over the particles and the bodies still to be added.
  const std::int64_t ids = model.staged ? model.id_count : static_cast<std::int64_t>(n);
  std::vector<bool> seen(static_cast<std::size_t>(ids), false);
  std::vector<std::size_t> flags;  // state columns of flag fields (written to frames as bytes)
  for (std::size_t k = 0; k < material_state_fields().size(); ++k)
    if (material_state_fields()[k].flag && p.state_held[k]) flags.push_back(k);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.body_p[i] < 0 || p.body_p[i] >= nbodies) in.fail(fmt::format("particle {} names body {}", i, p.body_p[i]));
    if (p.material_p[i] < 0 || p.material_p[i] >= nmat)
      in.fail(fmt::format("particle {} names material {}", i, p.material_p[i]));
    if (p.id_p[i] < 0 || p.id_p[i] >= ids || seen[static_cast<std::size_t>(p.id_p[i])])
      in.fail(fmt::format("particle {} has an invalid or repeated id {}", i, p.id_p[i]));
    seen[static_cast<std::size_t>(p.id_p[i])] = true;
    for (std::size_t k = 0; k < flags.size(); ++k) {
      const double v = p.state[flags[k]][i];
      if (!(v >= 0.0 && v <= 255.0 && v == std::floor(v)))
        in.fail(fmt::format("particle {} has {} = {}, expected a whole number from 0 to 255", i, p.state_name[flags[k]], v));
    }
    if (!(p.m_p[i] > 0.0) || !(p.V_p[i] > 0.0)) in.fail(fmt::format("particle {} has no mass or volume", i));
    for (int d = 0; d < D; ++d) {
      // The domain update keeps 0 < l_p <= h/2 (particle_domain.hpp); the GIMP weights assume it.
      if (!(p.l_p[i][d] > 0.0) || p.l_p[i][d] > 0.5 * model.grid.h * (1.0 + 1e-12))
        in.fail(fmt::format("particle {} has a domain half-width outside (0, h/2]", i));
      if (p.x_p[i][d] < model.grid.origin[d] || p.x_p[i][d] > model.grid.upper()[d])
        in.fail(fmt::format("particle {} lies outside the grid", i));
    }
  }
}

// Whether the checkpoint holds the surface loads (sections surface_loads, load.K.*).
template <int D>
bool holds_surface_loads(const Model<D>& model) {
  return model.staged || model.loads.any_follower();
}

}  // namespace

template <int D>
void write_checkpoint(const std::string& path, const Model<D>& model, const RunProgress& r) {
  Encoder e;
  e.bytes().append(magic, sizeof magic);
  e.raw(checkpoint_version);
  e.raw(static_cast<std::uint32_t>(D));
  e.raw(model.fingerprint);
  e.raw(static_cast<std::uint64_t>(model.particles.size()));
  e.scalar("time", r.time);
  e.scalar("steps", r.steps);
  e.scalar("dt", r.dt);
  e.scalar("frame_index", r.frame_index);
  e.scalar("row_index", r.row_index);
  e.scalar("label_index", r.label_index);
  e.scalar("last_frame", r.last_frame);
  e.scalar("last_row", r.last_row);
  model.particles.for_each_array([&](const char* name, const auto& a) { e.array(fmt::format("p.{}", name), a); });
  e.scalar("global_csv_bytes", r.output.global_bytes);
  e.scalar("global_csv_crc", r.output.global_crc);
  e.scalar("recorder_csv_bytes", r.output.recorder_bytes);
  e.scalar("recorder_csv_crc", r.output.recorder_crc);
  std::vector<double> frame_times;
  std::string frame_names;  // newline-separated
  for (const auto& [t, name] : r.output.frames) frame_times.push_back(t), frame_names += name + '\n';
  e.array("frame_times", frame_times);
  e.text("frame_names", frame_names);
  e.scalar("stage", r.stage);
  e.scalar("stage_done", static_cast<std::uint8_t>(r.stage_done));
  e.array("stage_starts", r.stage_starts);
  e.array("stage_start_steps", r.stage_start_steps);
  e.scalar("stage_peak_kinetic", r.stage_peak_kinetic);
  e.scalar("stage_first_frame", r.stage_first_frame);
  e.scalar("stages_csv_bytes", r.output.stages_bytes);
  e.scalar("stages_csv_crc", r.output.stages_crc);
  if (r.rest) {
    e.array("rest.anchor", r.rest_anchor);
    e.scalar("rest.largest", r.rest_largest);
    e.scalar("rest.ratio_start", r.rest_ratio_start);
  }
  // A staged run's surface loads were built on the particles of its stage's start, and a follower
  // pressure's forces have followed the deformation since (eq N1): both are state. A run with
  // neither rebuilds its loads from the input and writes no such section.
  if (holds_surface_loads(model)) {
    e.scalar("surface_loads", static_cast<std::uint64_t>(model.loads.surface.size()));
    for (std::size_t l = 0; l < model.loads.surface.size(); ++l) {
      e.array(fmt::format("load.{}.id", l), model.loads.surface[l].id);
      e.array(fmt::format("load.{}.force", l), model.loads.surface[l].force);
    }
  }
  e.raw(crc32_of(e.bytes()));
  write_file_atomically(path, e.bytes());
}

struct Header {
  std::uint64_t fingerprint = 0, particles = 0;
};

// The first header_size bytes (of `bytes`, which may hold more): magic, format version and
// dimension checked, the input fingerprint and the particle count returned.
template <int D>
Header read_header(std::string_view bytes, const std::string& source) {
  if (bytes.size() < header_size || std::memcmp(bytes.data(), magic, sizeof magic) != 0)
    refuse(source, "it does not start like a tsuchi checkpoint");
  auto field = [&](std::size_t at, auto v) {
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
  };
  const auto version = field(8, std::uint32_t{});
  const auto dim = field(12, std::uint32_t{});
  if (version != checkpoint_version)
    refuse(source, fmt::format("it has format version {}, this program reads version {}", version, checkpoint_version));
  if (dim != static_cast<std::uint32_t>(D)) refuse(source, fmt::format("it holds a {}D model, the input is {}D", dim, D));
  return {field(16, std::uint64_t{}), field(24, std::uint64_t{})};
}

template <int D>
RunProgress decode_checkpoint(std::string_view bytes, const std::string& source, Model<D>& model, bool verify_checksum,
                              const std::function<void(const RunProgress&)>& before_particles) {
  const auto fail = [&](const std::string& what) { refuse(source, what); };
  if (bytes.size() < header_size + 4) fail("it does not start like a tsuchi checkpoint");
  const auto [fp, count] = read_header<D>(bytes, source);
  const std::string_view body = bytes.substr(header_size, bytes.size() - header_size - 4);
  std::uint32_t stored_crc = 0;
  std::memcpy(&stored_crc, bytes.data() + bytes.size() - 4, 4);
  if (verify_checksum && stored_crc != crc32_of(bytes.substr(0, bytes.size() - 4)))
    fail("the checksum does not match: the file is damaged or incomplete");
  if (fp != model.fingerprint)
    fail(fmt::format("it was written for another input (the model, materials, bodies, boundary or solver "
                     "differ from {}); only time.end, time.max_steps, the time step, [output], [checkpoint] and "
                     "recorder stop bounds may change on a restart",
                     model.source));
  if (model.staged ? count > static_cast<std::uint64_t>(model.id_count) : count != model.particles.size())
    fail(fmt::format("it holds {} particles, the input makes {}", count, model.particles.size()));

  const Decoder in(body, source);
  RunProgress r;
  r.time = in.scalar<double>("time");
  r.steps = in.scalar<std::int64_t>("steps");
  r.dt = in.scalar<double>("dt");
  r.frame_index = in.scalar<std::int64_t>("frame_index");
  r.row_index = in.scalar<std::int64_t>("row_index");
  r.label_index = in.scalar<std::int64_t>("label_index");
  r.last_frame = in.scalar<double>("last_frame");
  r.last_row = in.scalar<double>("last_row");
  if (!std::isfinite(r.time) || r.time < 0.0 || r.steps < 0 || !std::isfinite(r.dt) || r.dt < 0.0 ||
      r.frame_index < 1 || r.row_index < 1 || r.label_index < 0 || !std::isfinite(r.last_frame) || !std::isfinite(r.last_row))
    in.fail("the time or the output counters are out of range");
  r.stage = in.scalar<std::int64_t>("stage");
  r.stage_done = in.scalar<std::uint8_t>("stage_done") != 0;
  const std::size_t starts = in.section("stage_starts").size() / sizeof(double);
  in.array("stage_starts", r.stage_starts, starts);
  in.array("stage_start_steps", r.stage_start_steps, starts);
  r.stage_peak_kinetic = in.scalar<double>("stage_peak_kinetic");
  r.stage_first_frame = in.scalar<std::int64_t>("stage_first_frame");
  r.output.stages_bytes = in.scalar<std::uint64_t>("stages_csv_bytes");
  r.output.stages_crc = in.scalar<std::uint32_t>("stages_csv_crc");
  r.rest = in.has("rest.largest");
  if (r.rest) {
    r.rest_largest = in.scalar<double>("rest.largest");
    r.rest_ratio_start = in.scalar<double>("rest.ratio_start");
    // D displacements per particle id (run/stage_rest.hpp), or none before a stage's first window.
    const std::size_t held = in.section("rest.anchor").size(), full = static_cast<std::size_t>(model.id_count) * D;
    if (held != 0 && held != full * sizeof(double))
      in.fail(fmt::format("section \"rest.anchor\" holds {} bytes, expected 0 or {} ({} per particle id, {} ids)", held,
                          full * sizeof(double), D, model.id_count));
    const std::size_t n = held / sizeof(double);
    in.array("rest.anchor", r.rest_anchor, n);
    if (!(r.rest_largest >= 0.0) || !std::isfinite(r.rest_largest) || std::isinf(r.rest_ratio_start))
      in.fail("the rest window is out of range");
    for (const double a : r.rest_anchor)
      if (!std::isfinite(a)) in.fail("the rest window is out of range");
  }
  const auto stages = static_cast<std::int64_t>(model.staged ? std::max<std::size_t>(model.stage_count, 1) : 1);
  const bool starts_ok = starts == static_cast<std::size_t>(r.stage) + 1 || (!model.staged && starts == 0);
  if (r.stage < 0 || r.stage >= stages || !starts_ok ||
      !std::isfinite(r.stage_peak_kinetic) || r.stage_first_frame < 0)
    in.fail("the stage counters are out of range");
  for (const double t : r.stage_starts)
    if (!std::isfinite(t) || t < 0.0 || t > r.time) in.fail("a stage's start time is out of range");
  if (before_particles) before_particles(r);
  if (count != model.particles.size())
    fail(fmt::format("it holds {} particles, the input makes {} at its stage", count, model.particles.size()));
  Particles<D> p;
  // A copy: clang before 16 cannot capture a structured binding in a lambda.
  const auto particle_count = static_cast<std::size_t>(count);
  // The file holds the optional arrays (APIC's C, sigma0, state columns) exactly when the input's
  // model does.
  p.same_arrays_as(model.particles);
  p.for_each_array([&](const char* name, auto& a) { in.array(fmt::format("p.{}", name), a, particle_count); });
  check_particles(p, model, in);
  r.output.global_bytes = in.scalar<std::uint64_t>("global_csv_bytes");
  r.output.global_crc = in.scalar<std::uint32_t>("global_csv_crc");
  r.output.recorder_bytes = in.scalar<std::uint64_t>("recorder_csv_bytes");
  r.output.recorder_crc = in.scalar<std::uint32_t>("recorder_csv_crc");
  std::vector<double> times;
  const std::string_view names_all = in.section("frame_names");
  const std::size_t nframes = static_cast<std::size_t>(std::count(names_all.begin(), names_all.end(), '\n'));
  in.array("frame_times", times, nframes);
  std::size_t at = 0;
  for (const double t : times) {
    const std::size_t end = names_all.find('\n', at);
    const std::string name(names_all.substr(at, end - at));
    at = end + 1;
    if (name.empty() || name.find('/') != std::string::npos || name.find('"') != std::string::npos ||
        name.find('<') != std::string::npos || name.find('&') != std::string::npos || !std::isfinite(t))
      in.fail("a frame entry is not a plain file name and time");
    r.output.frames.emplace_back(t, name);
  }
  if (holds_surface_loads(model)) {
    const auto loads = in.scalar<std::uint64_t>("surface_loads");
    if (loads != model.loads.surface.size()) in.fail("it holds another number of surface loads than the input's stage");
    for (std::size_t l = 0; l < model.loads.surface.size(); ++l) {
      auto& load = model.loads.surface[l];
      const std::size_t n = in.section(fmt::format("load.{}.id", l)).size() / sizeof(std::int64_t);
      in.array(fmt::format("load.{}.id", l), load.id, n);
      in.array(fmt::format("load.{}.force", l), load.force, n);
      for (const std::int64_t id : load.id)
        if (id < 0 || id >= model.id_count) in.fail("a surface load names a particle that does not exist");
      for (const Vec<D>& F : load.force)
        if (!F.allFinite()) in.fail("a surface load's force is not finite");
    }
  }
  model.particles = std::move(p);
  return r;
}

template <int D>
RunProgress read_checkpoint(const std::string& path, Model<D>& model,
                            const std::function<void(const RunProgress&)>& before_particles) {
  // The header first: a device, a pipe or a huge foreign file must not be read into memory.
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(fmt::format("{}: cannot open the checkpoint: {}", path, std::strerror(errno)));
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> closer(f, &std::fclose);
  struct stat st {};
  if (::fstat(::fileno(f), &st) != 0 || !S_ISREG(st.st_mode))
    refuse(path, "it is not a regular file (a directory, device or pipe)");
  std::string bytes(header_size, '\0');
  const std::size_t got = std::fread(bytes.data(), 1, header_size, f);
  const std::uint64_t count = read_header<D>(std::string_view(bytes).substr(0, got), path).particles;
  if (model.staged ? count > static_cast<std::uint64_t>(model.id_count) : count != model.particles.size())
    refuse(path, fmt::format("it holds {} particles, the input makes {}", count, model.particles.size()));
  // Every section but the frame list is a fixed size per particle, or per particle id (the rest
  // window, run/stage_rest.hpp: a staged run's ids include the bodies still to come); 64 bytes per
  // frame listed.
  const auto size = static_cast<std::uint64_t>(st.st_size);
  const std::uint64_t most = (count + 1) * 2 * model.particles.bytes_per_particle() +
                             static_cast<std::uint64_t>(model.id_count) * D * sizeof(double) + (std::uint64_t{1} << 30);
  if (size > most) refuse(path, fmt::format("it is {} bytes long, more than a checkpoint of {} particles can be", size, count));
  bytes.resize(static_cast<std::size_t>(size));
  const std::size_t rest = bytes.size() - header_size;
  if (std::fread(bytes.data() + header_size, 1, rest, f) != rest) refuse(path, "it could not be read to its end");
  return decode_checkpoint<D>(bytes, path, model, true, before_particles);
}

template void write_checkpoint<2>(const std::string&, const Model<2>&, const RunProgress&);
template void write_checkpoint<3>(const std::string&, const Model<3>&, const RunProgress&);
template RunProgress read_checkpoint<2>(const std::string&, Model<2>&, const std::function<void(const RunProgress&)>&);
template RunProgress read_checkpoint<3>(const std::string&, Model<3>&, const std::function<void(const RunProgress&)>&);
template RunProgress decode_checkpoint<2>(std::string_view, const std::string&, Model<2>&, bool, const std::function<void(const RunProgress&)>&);
template RunProgress decode_checkpoint<3>(std::string_view, const std::string&, Model<3>&, bool, const std::function<void(const RunProgress&)>&);

}  // namespace tsuchi
