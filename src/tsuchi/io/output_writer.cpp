#include "tsuchi/io/output_writer.hpp"

#include "tsuchi/io/atomic_file.hpp"
#include "tsuchi/io/vtu_writer.hpp"
#include "tsuchi/solver/global_quantities.hpp"

#include <fmt/format.h>

namespace tsuchi {

template <int D>
OutputWriter<D>::OutputWriter(const Model<D>& model, std::string directory)
    : m_(model), dir_(std::move(directory)) {
  prepare_output_directory(dir_);
  csv_ = "time,step,dt,kinetic_energy,strain_energy,gravity_potential,total_energy,mass";
  for (int d = 0; d < D; ++d) csv_ += fmt::format(",momentum_{}", "xyz"[d]);
  csv_ += '\n';
  for (const auto& rc : model.config.recorders) recorders_.emplace_back(rc, model);
  if (!recorders_.empty()) {
    recorder_csv_ = "time,step";
    for (const auto& r : recorders_) recorder_csv_ += "," + r.config().name;
    recorder_csv_ += '\n';
  }
}

template <int D>
void OutputWriter<D>::frame(double time) {
  if (!m_.config.output.write_frames) return;
  const std::string name = fmt::format("particles_{:06d}.vtu", frames_.size());
  write_file_atomically(dir_ + "/" + name, vtu_document<D>(m_, m_.config.output.fields));
  frames_.emplace_back(time, name);
  write_file_atomically(dir_ + "/particles.pvd", pvd_document(frames_));
  flush_global();
}

template <int D>
void OutputWriter<D>::global_row(double time, std::int64_t step, double dt) {
  const auto q = global_quantities<D>(m_);
  csv_ += fmt::format("{:.12g},{},{:.9g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g}", time, step, dt,
                      q.kinetic_energy, q.strain_energy, q.gravity_potential,
                      q.kinetic_energy + q.strain_energy + q.gravity_potential, q.mass);
  for (int d = 0; d < D; ++d) csv_ += fmt::format(",{:.12g}", q.momentum[d]);
  csv_ += '\n';
  if (recorders_.empty()) return;
  recorder_csv_ += fmt::format("{:.12g},{}", time, step);
  for (const auto& r : recorders_) recorder_csv_ += fmt::format(",{:.12g}", r.value(m_.particles));
  recorder_csv_ += '\n';
}

template <int D>
void OutputWriter<D>::flush_global() {
  write_file_atomically(dir_ + "/global.csv", csv_);
  if (!recorders_.empty()) write_file_atomically(dir_ + "/recorders.csv", recorder_csv_);
}

template class OutputWriter<2>;
template class OutputWriter<3>;

}  // namespace tsuchi
