#include "tsuchi/io/output_writer.hpp"

#include "tsuchi/io/paraview_view.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/atomic_file.hpp"
#include "tsuchi/io/grid_vtu_writer.hpp"
#include "tsuchi/io/vtu_writer.hpp"
#include "tsuchi/solver/global_quantities.hpp"
#include "tsuchi/solver/grid_projection.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace tsuchi {

namespace fs = std::filesystem;

namespace {

// HEAD, then at least `digits` decimal digits, then TAIL.
bool is_numbered_name(const std::string& name, const std::string& head, std::size_t digits, const std::string& tail) {
  if (name.size() < head.size() + digits + tail.size() || name.compare(0, head.size(), head) != 0 ||
      name.compare(name.size() - tail.size(), tail.size(), tail) != 0)
    return false;
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(head.size()),
                     name.end() - static_cast<std::ptrdiff_t>(tail.size()),
                     [](unsigned char c) { return c >= '0' && c <= '9'; });
}

// Absolute, symbolic links of the existing part resolved, "." and ".." and a trailing "/" gone.
fs::path normal(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec).lexically_normal();
  if (r.has_parent_path() && r.filename().empty()) r = r.parent_path();
  return r;
}

// The same file, whether or not it exists yet.
bool same_path(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return normal(a) == normal(b);
}

// grid_NNNNNN.vtu of particles_NNNNNN.vtu.
std::string grid_frame_name(const std::string& frame) { return "grid_" + frame.substr(std::string("particles_").size()); }

}  // namespace

bool is_frame_file_name(const std::string& name) { return is_numbered_name(name, "particles_", 6, ".vtu"); }

bool is_grid_frame_file_name(const std::string& name) { return is_numbered_name(name, "grid_", 6, ".vtu"); }

bool is_output_file_name(const std::string& name) {
  return name == "particles.pvd" || name == "particles_view.py" || name == "global.csv" || name == "recorders.csv" || name == "stages.csv" ||
         name == "contact.pvd" || name == "grid.pvd" || name == DirectoryLock::file_name || is_frame_file_name(name) ||
         is_grid_frame_file_name(name) ||
         is_numbered_name(name, "contact_", 1, ".vtu") || is_numbered_name(name, "particles_stage", 1, ".pvd") ||
         is_numbered_name(name, "grid_stage", 1, ".pvd");
}

void check_output_paths(const Config& c, const std::string& directory, const std::string& checkpoint) {
  const fs::path dir(directory), ck(checkpoint), input(c.source);
  const std::string& at = c.checkpoint.file_where.empty() ? c.source : c.checkpoint.file_where;
  auto refuse = [&](const std::string& what) {
    throw InputError(fmt::format("{}: key 'checkpoint.file': expected a file of its own, got \"{}\": {}", at,
                                 c.checkpoint.file, what));
  };
  std::error_code ec;
  if (same_path(ck, dir)) refuse(fmt::format("that is the output directory {}", directory));
  if (fs::is_directory(ck, ec)) refuse(fmt::format("{} is a directory", checkpoint));
  if (const std::string kind = non_regular_file_kind(checkpoint); !kind.empty())
    refuse(fmt::format("{} is {}, which the checkpoint (written as a new file renamed over the old) would replace by "
                       "a regular file",
                       checkpoint, kind));
  if (fs::exists(input, ec) && same_path(ck, input))
    refuse(fmt::format("{} is the input file, which the checkpoint would overwrite", checkpoint));
  for (const DataFile& f : c.data_files)
    if (same_path(ck, f.path))
      refuse(fmt::format("{} is a data file the input reads ({}), which the checkpoint would overwrite", checkpoint,
                         f.where));
  if (same_path(normal(ck).parent_path(), dir) && is_output_file_name(normal(ck).filename().string()))
    refuse(fmt::format("{} is one of the run's output files, which the checkpoint would overwrite", checkpoint));
  // The input file, or a file it reads, in the output directory under the name of a file the run
  // writes or removes there (the frames of an earlier run are removed at the start).
  const auto output_named = [&](const fs::path& p) {
    return fs::exists(p, ec) && same_path(normal(p).parent_path(), dir) && is_output_file_name(p.filename().string());
  };
  const std::string& dir_at = c.output.directory_where.empty() ? c.source : c.output.directory_where;
  if (output_named(input))
    throw InputError(fmt::format("{}: key 'output.directory': the input file is {}, an output file of this run in "
                                 "that directory; move the input or choose another output directory",
                                 dir_at, c.source));
  for (const DataFile& f : c.data_files)
    if (output_named(f.path))
      throw InputError(fmt::format("{}: the file {} is in the output directory {} under the name of an output file, "
                                   "which the run replaces or removes at its start; copy it elsewhere or choose "
                                   "another output directory (-o or output.directory at {})",
                                   f.where, f.path, directory, dir_at));
}

namespace {

// A restart continues the frames and CSV files of a directory that exists: one that does not is
// refused before prepare_output_directory would create it (and leave it behind, empty).
const std::string& existing_for_restart(const std::string& dir, const OutputHistory* resume) {
  std::error_code ec;
  if (resume && !fs::is_directory(dir, ec))
    throw InputError(fmt::format("cannot continue the run in {}: there is no such directory; restart into the output "
                                 "directory of the checkpointed run (-o), where its frames and CSV files are",
                                 dir));
  return dir;
}

}  // namespace

template <int D>
OutputWriter<D>::OutputWriter(const Model<D>& model, const OutputConfig& output, std::string directory,
                              std::vector<std::string> recorder_names, const OutputHistory* resume, bool staged,
                              bool contact_later)
    : m_(model),
      output_(output),
      dir_(std::move(directory)),
      lock_((prepare_output_directory(existing_for_restart(dir_, resume)), dir_)),
      recorders_(std::move(recorder_names)),
      staged_(staged) {
  std::string global_header = "time,step,dt,kinetic_energy,strain_energy,gravity_potential,total_energy,mass";
  for (int d = 0; d < D; ++d) global_header += fmt::format(",momentum_{}", "xyz"[d]);
  global_header += ",unbalanced_force_ratio,released_particles";
  const bool contact = contact_column_ = model.contact.active() || contact_later;
  global_header += contact ? ",contact_nodes" : "";
  global_header += staged ? ",stage\n" : "\n";
  std::string recorder_header;
  if (!recorders_.empty()) {
    recorder_header = "time,step";
    for (const auto& name : recorders_) recorder_header += "," + name;
    recorder_header += staged ? ",stage\n" : "\n";
  }
  if (resume) {
    h_ = *resume;
    for (const auto& [t, name] : h_.frames)
      if (!fs::exists(fs::path(dir_) / name))
        throw InputError(fmt::format("cannot continue the run in {}: frame {} of the checkpoint is not there; restart "
                                     "into the output directory of the checkpointed run (-o), where its frames are",
                                     dir_, name));
    global_.resume(dir_ + "/global.csv", h_.global_bytes, h_.global_crc);
    if (!recorders_.empty()) recorder_file_.resume(dir_ + "/recorders.csv", h_.recorder_bytes, h_.recorder_crc);
    if (staged_) stages_file_.resume(dir_ + "/stages.csv", h_.stages_bytes, h_.stages_crc);
  } else {
    global_.create(dir_ + "/global.csv", global_header);
    if (!recorders_.empty()) recorder_file_.create(dir_ + "/recorders.csv", recorder_header);
    if (staged_)
      stages_file_.create(dir_ + "/stages.csv",
                          "stage,name,end,start_time,end_time,start_step,end_step,unbalanced_force_ratio,"
                          "kinetic_energy_ratio,first_frame,last_frame\n");
  }
  // Frames of an earlier run (or written after the checkpoint by a killed one) would mix with this
  // run's in ParaView's view of the file series: remove every frame this run does not list.
  std::error_code ec;
  // Stages ended by the checkpoint's time: their rows in stages.csv (the header aside). A later
  // stage's .pvd was written by a killed run after the checkpoint and lists frames removed below.
  std::int64_t stages_ended = 0;
  if (resume && staged_) {
    std::ifstream in(dir_ + "/stages.csv", std::ios::binary);
    std::string text(static_cast<std::size_t>(h_.stages_bytes), '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    stages_ended = std::max<std::int64_t>(0, std::count(text.begin(), text.end(), '\n') - 1);
  }
  for (const auto& entry : fs::directory_iterator(dir_, ec)) {
    const std::string name = entry.path().filename().string();
    // contact_NNNNNN.vtu and grid_NNNNNN.vtu go with particles_NNNNNN.vtu: kept while that frame
    // is listed (grid frames only by a run that writes them).
    const bool grid_frame = is_grid_frame_file_name(name);
    const std::string frame = name.rfind("contact_", 0) == 0 ? "particles_" + name.substr(8)
                              : grid_frame                   ? "particles_" + name.substr(5)
                                                             : name;
    const bool listed = std::any_of(h_.frames.begin(), h_.frames.end(), [&](const auto& f) { return f.second == frame; });
    // particles_stageN.pvd, and grid_stageN.pvd with the grid frames.
    const bool grid_stage = name.rfind("grid_stage", 0) == 0;
    const std::size_t head = grid_stage ? 10 : 15;
    bool stage_pvd = (grid_stage || name.rfind("particles_stage", 0) == 0) && name.size() > head + 4 &&
                     name.compare(name.size() - 4, 4, ".pvd") == 0;
    if (stage_pvd && resume && !(grid_stage && output_.grid_fields.empty())) {
      const std::string digits = name.substr(head, name.size() - head - 4);
      const bool number = std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return c >= '0' && c <= '9'; });
      stage_pvd = number && digits.size() < 10 && std::stoll(digits) > stages_ended;  // stale: remove
    }
    if ((is_frame_file_name(frame) && !listed) || (name == "recorders.csv" && recorders_.empty()) ||
        (name == "stages.csv" && !staged_) || stage_pvd ||
        (name == "contact.pvd" && (h_.frames.empty() || !contact)) ||
        ((grid_frame || name == "grid.pvd") && output_.grid_fields.empty()))
      fs::remove(entry.path(), ec);
  }
  for (const auto& [label, name] : h_.frames) {
    const std::string own = "contact_" + name.substr(std::string("particles_").size());
    if (contact && fs::exists(fs::path(dir_) / own, ec)) contact_frames_.emplace_back(label, own);
  }
  // The grid frames of the frames listed, where there is one (a restart may switch grid_fields on).
  if (!output_.grid_fields.empty())
    for (const auto& [t, name] : h_.frames)
      if (const std::string grid = grid_frame_name(name); fs::exists(fs::path(dir_) / grid, ec))
        grid_frames_.emplace_back(t, grid);
  if (grid_frames_.empty()) fs::remove(dir_ + "/grid.pvd", ec);
  else write_file_atomically(dir_ + "/grid.pvd", pvd_document(grid_frames_));
  const std::string pvd = dir_ + "/particles.pvd";
  if (h_.frames.empty()) fs::remove(pvd, ec), fs::remove(dir_ + "/particles_view.py", ec);
  else write_file_atomically(pvd, pvd_document(h_.frames));
}

template <int D>
void OutputWriter<D>::frame(double label, const ContactPoints* contact) {
  if (!output_.write_frames) return;
  const std::string name = fmt::format("particles_{:06d}.vtu", h_.frames.size());
  if (contact) {
    // Written before the particle frame: the .pvd lists a contact frame only once both exist.
    write_file_atomically(dir_ + "/" + fmt::format("contact_{:06d}.vtu", h_.frames.size()), contact_vtu_document(*contact));
  }
  // Grid frames (output.grid_fields) too are written before the particle frame: grid.pvd lists
  // only grid frames whose particle frame is there. The solver computes, io writes.
  const std::string grid = grid_frame_name(name);
  if (!output_.grid_fields.empty())
    write_file_atomically(dir_ + "/" + grid, grid_vtu_document<D>(m_, project_to_grid<D>(m_, output_.grid_fields)));
  write_file_atomically(dir_ + "/" + name, vtu_document<D>(m_, output_.fields));
  h_.frames.emplace_back(label, name);
  write_file_atomically(dir_ + "/particles.pvd", pvd_document(h_.frames));
  if (!output_.grid_fields.empty()) {
    grid_frames_.emplace_back(label, grid);
    write_file_atomically(dir_ + "/grid.pvd", pvd_document(grid_frames_));
  }
  // The ParaView view of the frames (io/paraview_view.hpp), with the first frame of this process.
  if (!view_written_) {
    write_file_atomically(dir_ + "/particles_view.py", paraview_view_script(D, output_.fields, m_.grid.h, !output_.grid_fields.empty()));
    view_written_ = true;
  }
  if (contact) {
    contact_frames_.emplace_back(label, "contact_" + name.substr(std::string("particles_").size()));
    write_file_atomically(dir_ + "/contact.pvd", pvd_document(contact_frames_));
  }
  flush_global();
}

template <int D>
void OutputWriter<D>::global_row(double time, std::int64_t step, double dt, const StepReport& report,
                                 const std::vector<double>& recorder_values) {
  const auto q = global_quantities<D>(m_);
  std::string row = fmt::format("{:.12g},{},{:.9g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g}", time, step, dt,
                                q.kinetic_energy, q.strain_energy, q.gravity_potential,
                                q.kinetic_energy + q.strain_energy + q.gravity_potential, q.mass);
  for (int d = 0; d < D; ++d) row += fmt::format(",{:.12g}", q.momentum[d]);
  row += fmt::format(",{:.6g},{}", report.unbalanced_force_ratio, report.released_particles);
  // 0 in a stage without contact, when a later stage has it.
  row += contact_column_ ? fmt::format(",{}", std::max<std::int64_t>(0, report.contact_nodes)) : std::string{};
  row += staged_ ? fmt::format(",{}\n", stage_) : std::string("\n");
  global_.append(row);
  if (recorders_.empty()) return;
  row = fmt::format("{:.12g},{}", time, step);
  for (const double v : recorder_values) row += fmt::format(",{:.12g}", v);
  row += staged_ ? fmt::format(",{}\n", stage_) : std::string("\n");
  recorder_file_.append(row);
}

template <int D>
void OutputWriter<D>::stage_row(const StageRow& r) {
  // Quoted: a stage's name may hold a comma.
  std::string name;
  for (const char ch : r.name) name += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  stages_file_.append(fmt::format("{},\"{}\",{},{:.12g},{:.12g},{},{},{:.6g},{:.6g},{},{}\n", r.stage, name, r.end,
                                  r.start_time, r.end_time, r.start_step, r.end_step, r.unbalanced_force_ratio,
                                  r.kinetic_energy_ratio, r.first_frame, r.last_frame));
  if (r.last_frame >= r.first_frame && static_cast<std::size_t>(r.last_frame) < h_.frames.size()) {
    const std::vector<std::pair<double, std::string>> frames(h_.frames.begin() + r.first_frame,
                                                             h_.frames.begin() + r.last_frame + 1);
    write_file_atomically(fmt::format("{}/particles_stage{}.pvd", dir_, r.stage), pvd_document(frames));
    // The stage's grid frames, those of its frames that have one (a restart may switch them on).
    std::vector<std::pair<double, std::string>> grid;
    for (const auto& f : frames) {
      const std::string grid_name = grid_frame_name(f.second);
      if (std::any_of(grid_frames_.begin(), grid_frames_.end(), [&](const auto& g) { return g.second == grid_name; }))
        grid.emplace_back(f.first, grid_name);
    }
    if (!grid.empty()) write_file_atomically(fmt::format("{}/grid_stage{}.pvd", dir_, r.stage), pvd_document(grid));
  }
  flush_global();
}

template <int D>
void OutputWriter<D>::flush_global(bool sync) {
  global_.flush(sync);
  recorder_file_.flush(sync);
  stages_file_.flush(sync);
}

template <int D>
OutputHistory OutputWriter<D>::history() const {
  OutputHistory h;
  h.frames = h_.frames;
  h.global_bytes = global_.bytes();
  h.global_crc = global_.crc();
  h.recorder_bytes = recorder_file_.bytes();
  h.recorder_crc = recorder_file_.crc();
  h.stages_bytes = stages_file_.bytes();
  h.stages_crc = stages_file_.crc();
  return h;
}

template class OutputWriter<2>;
template class OutputWriter<3>;

}  // namespace tsuchi
