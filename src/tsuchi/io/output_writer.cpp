#include "tsuchi/io/output_writer.hpp"

#include "tsuchi/io/atomic_file.hpp"
#include "tsuchi/io/vtu_writer.hpp"
#include "tsuchi/solver/global_quantities.hpp"

#include <fmt/format.h>

namespace tsuchi {

template <int D>
OutputWriter<D>::OutputWriter(const Model<D>& model, std::string directory, const std::vector<Recorder<D>>& recorders)
    : m_(model), dir_(std::move(directory)), recorders_(recorders) {
  prepare_output_directory(dir_);
  h_.global_csv = "time,step,dt,kinetic_energy,strain_energy,gravity_potential,total_energy,mass";
  for (int d = 0; d < D; ++d) h_.global_csv += fmt::format(",momentum_{}", "xyz"[d]);
  h_.global_csv += '\n';
  if (!recorders_.empty()) {
    h_.recorder_csv = "time,step";
    for (const auto& r : recorders_) h_.recorder_csv += "," + r.config().name;
    h_.recorder_csv += '\n';
  }
}

template <int D>
void OutputWriter<D>::frame(double time) {
  if (!m_.config.output.write_frames) return;
  const std::string name = fmt::format("particles_{:06d}.vtu", h_.frames.size());
  write_file_atomically(dir_ + "/" + name, vtu_document<D>(m_, m_.config.output.fields));
  h_.frames.emplace_back(time, name);
  write_file_atomically(dir_ + "/particles.pvd", pvd_document(h_.frames));
  flush_global();
}

template <int D>
void OutputWriter<D>::global_row(double time, std::int64_t step, double dt) {
  const auto q = global_quantities<D>(m_);
  h_.global_csv += fmt::format("{:.12g},{},{:.9g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g}", time, step, dt,
                      q.kinetic_energy, q.strain_energy, q.gravity_potential,
                      q.kinetic_energy + q.strain_energy + q.gravity_potential, q.mass);
  for (int d = 0; d < D; ++d) h_.global_csv += fmt::format(",{:.12g}", q.momentum[d]);
  h_.global_csv += '\n';
  if (recorders_.empty()) return;
  h_.recorder_csv += fmt::format("{:.12g},{}", time, step);
  for (const auto& r : recorders_) h_.recorder_csv += fmt::format(",{:.12g}", r.value(m_.particles));
  h_.recorder_csv += '\n';
}

template <int D>
void OutputWriter<D>::flush_global() {
  write_file_atomically(dir_ + "/global.csv", h_.global_csv);
  if (!recorders_.empty()) write_file_atomically(dir_ + "/recorders.csv", h_.recorder_csv);
}

template class OutputWriter<2>;
template class OutputWriter<3>;

}  // namespace tsuchi
