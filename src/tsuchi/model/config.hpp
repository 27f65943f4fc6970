#pragma once
// The whole input of a run as a typed, validated value. Read from a TOML file by
// io/config_reader.hpp; vectors have `dimension` meaningful entries (the third is 0 in 2D).
#include "tsuchi/core/time_function.hpp"
#include "tsuchi/geometry/shape.hpp"
#include "tsuchi/material/material.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tsuchi {

using Triple = std::array<double, 3>;

enum class Scheme { USF, USL, MUSL };
enum class ShapeKind { Linear, UGimp, Gimp };
// Friction: a rigid wall the material may slide along (Coulomb, BoundaryConfig::face_friction) and
// leave, but not cross (model/contact.hpp).
enum class FaceCondition { Free, Roller, Fixed, Friction };
// A grid face numbered axis * 2 + side (side 1 the upper one) as the input names it: "y_min".
inline std::string face_name(int face) { return std::string(1, "xyz"[face / 2]) + (face % 2 ? "_max" : "_min"); }
// How velocities go between particles and grid: FLIP (blended with PIC by pic_fraction) or APIC
// (Jiang et al. 2015), which carries an affine velocity field per particle.
enum class VelocityTransfer { Flip, Apic };
// How the volumetric strain increment of a particle is taken (solver/volumetric_strain.hpp): its
// own (the GIMP/linear gradient at the particle, which locks in isochoric flow); that of the
// centre of the background cell holding it (mean dilatation per cell); or the volume-weighted
// average of the particles' increments through the nodes (F-bar by P2G/G2P averaging); or that
// average with its transpose in the internal force as well (a symmetric B-bar pair).
enum class AntiLocking { None, Cell, Node, Bbar };

// Whether the remedy takes the nodal average of the volumetric strain (eq V3).
constexpr bool node_averaged(AntiLocking a) { return a == AntiLocking::Node || a == AntiLocking::Bbar; }

// A named function of time from the input's [[functions]]: loads refer to it by name and are
// multiplied by it (core/time_function.hpp).
struct FunctionConfig {
  std::string name;
  TimeFunction f;
  // Set by the reader when a key names the function (io::read_function_ref): one nothing names is
  // worth a warning (a load that forgot its `function`), kept here with its place in the file.
  mutable bool named = false;
  std::string unused_warning;
};

struct GridConfig {
  Triple origin{};
  Triple extent{};
  double cell_size = 0.0;
  std::array<int, 3> cells{1, 1, 1};
};

// Initial stress of a body, tension positive (Pa). The particles start with sigma = sigma0; with
// `subtract` the internal force uses sigma - sigma0 (eq 2), so sigma0 holds itself like a confining
// pressure on every face, and only the change of stress moves the body.
struct InitialStressConfig {
  enum class Kind { None, Uniform, K0 };
  Kind kind = Kind::None;
  std::array<double, 6> tensor{};  // Uniform: xx, yy, zz, xy, yz, xz
  // K0: sigma_h = k0 sigma_v, sigma_v = surface_stress - |g| * (integral of rho over the material
  // above the particle, along gravity: model/overburden.hpp).
  double k0 = 0.0;
  // K0, when given: a level free surface at this coordinate of the up axis and the particle's own
  // density all the way up, sigma_v = surface_stress - rho |g| (surface - x_up) (the meaning
  // before shaped bodies).
  std::optional<double> surface;
  double surface_stress = 0.0;     // K0: the surcharge on top of every column (Pa, tension positive)
  bool subtract = false;
  std::string where;               // "FILE:LINE:COL" of the table, for messages ("" when not given)
};

// Random strength imperfection: c and/or phi of each particle times (1 + d), d uniform in [-a, a].
struct ImperfectionConfig {
  double amplitude = 0.0;
  std::uint64_t seed = 0;
  bool cohesion = false;
  bool friction = false;
};

// Part of a body with another material (layered ground in one body): a particle of the body
// inside the shape takes `material`; a later region of the body wins over an earlier one.
struct RegionConfig {
  std::string material;
  int material_index = 0;
  geometry::ShapePtr shape;
  std::string kind;  // the shape's kind as written ("box", "polygon", ...), for the summary
};

// Particles read from a file (io/particle_file_reader.hpp) instead of a shape: positions, volumes
// and any particle field given there. Columns are named like recorder quantities
// ("velocity_x", "stress_xy", a material state field's name).
struct ParticleTable {
  std::string file;                   // as given, for messages
  std::vector<Triple> x;              // position (m)
  std::vector<double> volume;         // m^3 (m^2 per metre in 2D)
  std::vector<std::string> where;     // "FILE:LINE" or "FILE: point N" of each row, for messages
  std::vector<std::string> columns;   // further columns: a particle field component each
  std::vector<std::vector<double>> values;  // values[column][row]
  std::uint64_t digest = 0;           // of the file's bytes, for Config::fingerprint
  // Particles whose edge is below 1/20 of a cell (io/particle_file_reader.cpp): their count, the
  // first one's "FILE:LINE" and the smallest edge, for a warning.
  std::size_t small_particles = 0;
  std::string first_small;
  double smallest_edge = 0.0;
};

struct BodyConfig {
  std::string name;
  std::string material;
  int material_index = 0;
  // The region the body fills (a box from min/max when no `shape` is given), or null when the
  // particles come from a file.
  geometry::ShapePtr shape;
  std::string shape_kind;      // "box", "polygon", ... or "file"
  std::string shape_key;       // the key messages about the body's geometry point at ("min", "shape", "particles")
  std::string shape_where;     // "FILE:LINE:COL" of that key
  int priority = 0;            // where bodies overlap, the higher priority keeps the particles
  std::vector<RegionConfig> regions;
  std::shared_ptr<const ParticleTable> particles;  // particles = "FILE"
  std::array<int, 3> particles_per_cell{2, 2, 2};
  Triple velocity{};
  std::array<std::string, 3> velocity_formula;  // when set, replaces velocity[d]: a formula of x, y, z
  std::string velocity_where;                    // "FILE:LINE:COL" of 'velocity', for messages
  // Prescribed particle velocity (a loading platen): component d is held at
  // prescribed_velocity[d] + sum_j prescribed_gradient[d][j] x_j when prescribed[d] is set.
  std::array<bool, 3> prescribed{false, false, false};
  Triple prescribed_velocity{};
  std::array<Triple, 3> prescribed_gradient{};
  int prescribed_velocity_function = -1;  // index in Config::functions: the prescribed velocity times f(t); -1: none
  // > 0: a rigid body of this mass (kg; kg per metre in 2D) in contact: the components not in
  // prescribed_velocity translate under gravity and the contact forces (model/contact.hpp).
  double rigid_mass = 0.0;
  InitialStressConfig initial_stress;
  ImperfectionConfig imperfection;
};

// [[boundary.nodes]]: the grid nodes in a box, with components held at zero (`fix`) and/or driven
// (base motion, docs/input.md): component d with driven[d] follows v_d(t) = value_d f(t) (Velocity)
// or v_d(t) = initial_velocity_d + value_d * integral_0^t f (Acceleration), f = functions[function]
// (1 when function < 0). Where sets overlap, the later set decides a component it names.
struct NodeSetConfig {
  enum class Drive { None, Velocity, Acceleration };
  std::string name;  // "" when unnamed; a reaction recorder names the set by it
  Triple min{}, max{};
  std::array<bool, 3> fix{false, false, false};
  Drive drive = Drive::None;
  std::array<bool, 3> driven{false, false, false};
  Triple value{};             // m/s (Velocity) or m/s^2 (Acceleration)
  Triple initial_velocity{};  // Acceleration: v(0), m/s
  int function = -1;          // index in Config::functions, -1: f = 1
};

struct BoundaryConfig {
  // faces[axis][0] is the lower face, [1] the upper one.
  std::array<std::array<FaceCondition, 2>, 3> faces{};
  // FaceCondition::Friction: the wall's Coulomb coefficient, [axis][side]; +infinity for "rough".
  std::array<std::array<double, 2>, 3> face_friction{};
  std::vector<NodeSetConfig> node_sets;
};

// [[contact]]: how two bodies meet (model/contact.hpp). Bodies not named in a frictional or rough
// pair share one velocity field and so stay bonded, as every body did before contact.
struct ContactConfig {
  enum class Law { Frictional, Rough, Bonded };
  int body_a = -1, body_b = -1;  // indices in Config::bodies
  Law law = Law::Frictional;
  double friction = 0.0;         // Law::Frictional: Coulomb coefficient mu >= 0 (0: frictionless)
  std::string where;             // "FILE:LINE:COL: key 'contact.N'" prefix, for messages at build time
};

// A load of the input's [[loads]] (docs/input.md, model/loads.hpp), times its function of time.
struct LoadConfig {
  enum class Kind { Traction, NodalForce, BodyForce };
  Kind kind = Kind::Traction;
  std::string where;  // "FILE:LINE:COL: key 'loads.N'" prefix for messages raised when the model is built
  int function = -1;  // index in Config::functions; -1: constant
  int body = -1;      // traction: the loaded body; body_force: the body, or -1 for every body
  // traction: the particles selected by the box of initial positions [min, max], or by the plane
  // through plane_point with normal plane_normal (pointing out of the body).
  bool by_plane = false;
  Triple min{}, max{};               // traction (box) and nodal_force: the box
  Triple plane_point{}, plane_normal{};
  bool pressure_given = false;       // traction: pressure (Pa, pushing inwards) instead of a traction vector
  double pressure = 0.0;
  bool follow = false;               // pressure: a follower load (area vectors by Nanson's relation, solver/follower_area.hpp)
  Triple vector{};                   // traction (Pa), nodal_force's total force (N; N/m in 2D), body_force (N/m^3)
};

struct SolverConfig {
  Scheme scheme = Scheme::MUSL;
  ShapeKind shape = ShapeKind::Gimp;
  double pic_fraction = 0.0;       // 0 = pure FLIP, 1 = pure PIC
  VelocityTransfer velocity_transfer = VelocityTransfer::Apic;  // APIC only with pic_fraction = 0
  // Every material's, unless materials.N.anti_locking says; when the input gives none, a material
  // whose plastic flow dilates takes None instead (anti_locking_of below).
  AntiLocking anti_locking = AntiLocking::Node;
  bool anti_locking_given = false;  // solver.anti_locking was in the input
  // A particle whose stress the last update released in tension keeps its volume when the step
  // would expand it: the opening is a gap between particles, not a looser material.
  bool hold_released_volume = true;
  double damping = 0.0;            // Cundall local damping coefficient alpha, eq (20)
  double mass_threshold = 1e-9;    // nodes lighter than this fraction of the lightest particle are skipped
  // Particles are re-stored in block order every this many steps (0: never), so that neighbours
  // in space stay neighbours in memory as the material flows.
  std::int64_t sort_interval = 100;
};

struct TimeConfig {
  double end = 0.0;
  std::optional<double> courant;   // exactly one of courant and dt is set
  std::optional<double> dt;
  std::int64_t max_steps = 0;      // 0: no limit
  std::string dt_where;            // "FILE:LINE:COL" of time.dt, for messages ("" when not given)
};

// When the run saves its whole state for a restart (io/checkpoint.hpp). A checkpoint is also
// written on SIGINT / SIGTERM and at the end of a run that has either interval set.
struct CheckpointConfig {
  std::int64_t every_steps = 0;    // 0: not by step count
  double every_minutes = 0.0;      // 0: not by wall time
  std::string file = "checkpoint.tsuchi";  // relative to the output directory unless absolute
  std::string file_where;                  // "FILE:LINE:COL" of the key, for messages ("" when not given)
  bool enabled() const { return every_steps > 0 || every_minutes > 0.0; }
};

struct OutputConfig {
  std::string directory = "results";
  std::string directory_where;     // "FILE:LINE:COL" of the key, for messages ("" when not given)
  double interval = 0.0;           // s between particle frames; 0 writes only the first and last
  double global_interval = 0.0;    // s between rows of the global CSV; 0: every step
  std::vector<std::string> fields;  // particle fields in the .vtu frames
  // Particle fields projected to the grid's nodes in grid_NNNNNN.vtu beside each frame
  // (solver/grid_projection.hpp); empty: no grid frames.
  std::vector<std::string> grid_fields;
  std::string grid_fields_where;    // "FILE:LINE:COL" of the key ("" when not given)
  bool write_frames = true;
  // A recorder that labels the frames: its value is each frame's "timestep" in the .pvd (so
  // ParaView's time axis is, say, the axial strain). With label_interval > 0 a frame is also
  // written after the step at which the recorder passes each multiple k * label_interval.
  std::string frame_label;          // "" = frames labelled by time
  int frame_label_recorder = -1;    // its index in Config::recorders
  double label_interval = 0.0;
};

// A recorded quantity: `reduction` over a particle set of one per-particle quantity, written as
// scale * value + offset to recorders.csv; optionally the run stops when it crosses a bound.
// The recorder quantity that is a whole-model number rather than a reduction over particles:
// the solver's unbalanced-force ratio (ExplicitSolver::unbalanced_force_ratio()). A recorder of
// it takes no body, min, max or reduction.
inline constexpr const char* kUnbalancedForceRatio = "unbalanced_force_ratio";

// reaction_x, reaction_y, reaction_z: the force that holds a prescribed-motion body to its motion
// (ExplicitSolver::reaction()), or that the supports exert at a grid face or node set
// (ExplicitSolver::support_reaction()). A recorder of it names the body, the face or the node set
// and takes no min, max or reduction.
inline constexpr std::string_view kReactionPrefix = "reaction_";

struct RecorderConfig {
  enum class Reduction { Mean, Sum, Min, Max };
  bool whole_model() const { return quantity == kUnbalancedForceRatio; }
  // The axis of a reaction_ quantity, or -1.
  int reaction_axis() const {
    if (quantity.size() != kReactionPrefix.size() + 1 || quantity.rfind(kReactionPrefix, 0) != 0) return -1;
    const char a = quantity.back();
    return a == 'x' ? 0 : a == 'y' ? 1 : a == 'z' ? 2 : -1;
  }
  // A number the solver computes in a step, with no value before the first one.
  bool from_solver() const { return whole_model() || reaction_axis() >= 0; }
  std::string name;
  int body = -1;                       // -1: every body
  // reaction_*: the support force at a grid face (axis * 2 + side; -1: none) or a named node set
  // (index in BoundaryConfig::node_sets; -1: none) instead of a body.
  int face = -1;
  int node_set = -1;
  std::optional<Triple> min, max;      // box of initial positions; unset: no limit
  std::string quantity;                // e.g. "stress_yy", "displacement_x", "max_shear_strain"
  Reduction reduction = Reduction::Mean;
  double scale = 1.0, offset = 0.0;
  std::optional<double> stop_above, stop_below;
  std::string where;  // "FILE:LINE:COL" of the table, for the errors found when the model is built
};

struct Config;

// How a stage of a staged run ends (docs/stages.md): at the first of the ends it gives. A stage
// with no duration or step count must give max_steps, so that it cannot run forever.
struct StageEnd {
  std::optional<double> duration;        // s after the stage's start
  std::int64_t steps = 0;                // steps of the stage; 0: not by steps
  // Equilibrium: the unbalanced-force ratio and/or the kinetic-energy ratio (kinetic energy over
  // its largest value in the stage) below these, checked once any gravity ramp of the stage is over.
  std::optional<double> unbalanced_force_ratio;
  std::optional<double> kinetic_energy_ratio;
  // An equilibrium stage also ends when its ground is at rest on the ratio's floor (run/stage_rest.hpp).
  bool at_rest = true;
  int recorder = -1;                     // index in Config::recorders: a stop bound for this stage
  std::optional<double> above, below;
  std::int64_t max_steps = 0;            // 0: none (then duration or steps is given)
  bool equilibrium() const { return unbalanced_force_ratio || kinetic_energy_ratio; }
  // Judged at rest on the ratio's floor as well (run/stage_rest.hpp).
  bool judged_at_rest() const { return equilibrium() && at_rest; }
};

// A part of the model that a stage removes or adds by its shape (an entry of `remove` / `add` that
// is a table): a cut in layers, a tunnel's advance, a fill in lifts, without a body per part.
// remove: the particles of `bodies` (every body there when empty) whose centre lies inside `shape`
// at the stage's start; add: the waiting particles of `bodies` (a body a stage adds, Model::dormant)
// inside it.
struct StageRegionConfig {
  std::vector<int> bodies;
  geometry::ShapePtr shape;
  std::string kind;      // the shape's kind as written, for messages
  std::string key_path;  // "stages.K.remove.J", for messages
  std::string where;     // "FILE:LINE:COL" of the entry
};

// A stage of [[stages]]: what changes at its start and how it ends. `config` is the whole input as
// it stands during the stage (the file with the changes of this and every earlier stage merged in).
struct StageConfig {
  std::string name;
  std::string where;                     // "FILE:LINE:COL" of the stage's table, for messages
  StageEnd end;
  std::vector<int> remove, add;          // bodies removed (excavation) / added (fill) at the start
  std::vector<StageRegionConfig> remove_regions, add_regions;  // and parts of bodies, by shape
  bool reset_displacements = false;      // displacements and strains set to zero at the start
  // Which parts of the input the stage changes: their functions of time start at the stage's start,
  // and only they are rebuilt (an unchanged load keeps its particles and forces).
  bool changes_gravity = false, changes_loads = false, changes_boundary = false;
  // Which functions of time the stage sets (they start with it; the others keep their clocks).
  bool sets_gravity_function = false, sets_node_sets = false;
  bool changes_materials = false, changes_solver = false;
  bool changes_contact = false;          // [[stages.contact]]: every pair replaced (contact = []: none)
  std::vector<int> changes_motion;       // bodies whose prescribed motion the stage sets
  std::vector<int> changes_body_material;  // bodies given another material
  std::shared_ptr<const Config> config;
};

// [fos]: the factor of safety by strength reduction (`tsuchi fos`, run/factor_of_safety.hpp).
struct FosConfig {
  bool given = false;
  int after_stage = -1;                  // index in Config::stages; -1: after the whole run (unstaged input)
  bool reduce_dilatancy = false;         // psi by tan(psi) / F as well; else psi = min(psi, phi_F)
  double lower = 1.0, upper = 2.0;       // the first bracket; the upper end grows until a trial fails
  double tolerance = 0.01;               // stop when (upper - lower) / lower is below this
  std::int64_t max_steps = 0;            // per trial: no equilibrium by then is a failure
  double unbalanced_force_ratio = 1e-3;  // a trial is in equilibrium below this ratio (near failure it levels off at 1e-3 to 1e-2)
  std::optional<double> displacement_limit;  // a trial fails once a particle moves more than this (m)
  int trials_at_once = 2;                // trials per round (bisection for 1); the same on any thread count
  // A trial still slowing down at max_steps may go on, a fifth of max_steps at a time, up to this
  // many times max_steps (run/factor_of_safety.cpp); 1: judged at max_steps.
  std::int64_t extend = 4;
  // The fewest steps a trial may be given: its ratio is judged from its 20th step
  // (equilibrium_first_step, run/simulation.hpp) and its rest over its last fifth, which must then
  // start after that (fos.max_steps = 1 gave "the ground stands at F = 64").
  static constexpr std::int64_t min_steps = 100;
};

// A data file the input reads (a record, an STL surface, a particle file): the output and the
// checkpoint must never overwrite or remove it.
struct DataFile {
  std::string path;   // as opened (relative to the working directory, or absolute)
  std::string where;  // "FILE:LINE:COL: key 'PATH'" of the key that names it, for messages
};

struct Config {
  std::string source;  // file the configuration came from, for messages
  std::string title;
  int dimension = 2;
  Triple gravity{};
  int gravity_function = -1;  // index in functions: gravity(t) = gravity f(t); -1: constant
  std::vector<FunctionConfig> functions;
  GridConfig grid;
  std::vector<Material> materials;
  // Per material, materials.N.anti_locking where given; otherwise solver.anti_locking holds.
  std::vector<std::optional<AntiLocking>> material_anti_locking;
  std::vector<BodyConfig> bodies;
  BoundaryConfig boundary;
  SolverConfig solver;
  TimeConfig time;
  OutputConfig output;
  CheckpointConfig checkpoint;
  std::vector<RecorderConfig> recorders;
  std::vector<LoadConfig> loads;
  std::vector<ContactConfig> contacts;
  // [[stages]], in order; empty for a single-stage input. The Config itself is then the first
  // stage's (stages[0].config holds the same).
  std::vector<StageConfig> stages;
  FosConfig fos;
  // Bodies that a stage adds: absent until then (their particles wait in Model::dormant).
  std::vector<bool> body_starts_dormant;
  bool staged() const { return !stages.empty(); }
  // Hash of everything that decides the state of a run (not the end time, step limit, output,
  // checkpoint schedule, time step choice, stop bounds or title): a checkpoint restarts only a
  // configuration with the same fingerprint.
  std::uint64_t fingerprint = 0;
  // Digests of the data files the input names (records, surfaces, particle files), folded into the
  // fingerprint: a restart with a changed record is a different run.
  std::vector<std::uint64_t> file_digests;
  // Every data file the input reads, in the order read.
  std::vector<DataFile> data_files;
  // Valid values that look like a slip of units ("FILE:LINE:COL: key '...': ..."); printed, not refused.
  std::vector<std::string> warnings;
};

// The remedy material k takes: materials.N.anti_locking, else solver.anti_locking where the input
// gives it, else Node, or None for a material whose plastic flow dilates (psi > 0). An average of
// the volumetric strain cannot follow the dilation of the points that shear (a band's points
// must swell, their neighbours not), so it compresses them elastically and raises their strength:
// the paper's triaxial test 1 at psi = 10 deg peaked 20 % above Mohr-Coulomb with Node or Bbar and
// 1.7 % above with None. And the averaged pairs run away on a homogeneous element of dilatant
// Mohr-Coulomb: with Node in plane strain, where the mode stretching a yielding point along its
// minor stress does negative work once
//   sin psi > (1 - 2 nu) / 3                                                                   (V6)
// (psi = 10 deg, nu = 0.3: particle stresses -40 to -480 kPa about a peak of -335), and with Node
// and Bbar in 3D (triaxial compression, from psi = 0 for Bbar); None holds every point on the peak
// (tests/numerics_test.cpp, docs/input.md [solver]). A dilatant flow is not isochoric, so the
// locking the averages are for is smaller.
inline AntiLocking anti_locking_of(const Config& c, std::size_t k) {
  if (k < c.material_anti_locking.size() && c.material_anti_locking[k]) return *c.material_anti_locking[k];
  if (c.solver.anti_locking_given) return c.solver.anti_locking;
  return k < c.materials.size() && dilatancy_angle_of(c.materials[k]) > 0.0 ? AntiLocking::None : AntiLocking::Node;
}

const char* to_string(Scheme s);
const char* to_string(ShapeKind s);
const char* to_string(VelocityTransfer t);
const char* to_string(AntiLocking a);

}  // namespace tsuchi
