#pragma once
// The files a run writes into its output directory:
//   particles_NNNNNN.vtu  one frame per output interval (binary VTK XML)
//   particles.pvd         the time series ParaView opens, listing only complete frames
//   global.csv            time series of whole-model quantities
//   recorders.csv         time series of the input's recorders (when it has any), same rows
// Every file is replaced atomically, so a run killed at any moment leaves only complete files.
#include "tsuchi/model/model.hpp"
#include "tsuchi/solver/recorder.hpp"

#include <string>
#include <utility>
#include <vector>

namespace tsuchi {

// Everything the files above hold so far, kept in memory so each rewrite is whole; a checkpoint
// saves it and a restart puts it back.
struct OutputHistory {
  std::vector<std::pair<double, std::string>> frames;  // (time, file name) listed in the .pvd
  std::string global_csv;
  std::string recorder_csv;  // empty when the input has no recorders
};

template <int D>
class OutputWriter {
 public:
  // `recorders` are the run's (chosen on the initial state) and must outlive the writer.
  OutputWriter(const Model<D>& model, std::string directory, const std::vector<Recorder<D>>& recorders);

  void frame(double time);
  void global_row(double time, std::int64_t step, double dt);
  // Rewrites global.csv with all rows so far; done with every frame and at the end of a run (and
  // by the run loop every half minute), not per row, so long runs do not rewrite it per step.
  void flush_global();

  const std::string& directory() const { return dir_; }
  std::size_t frames_written() const { return h_.frames.size(); }
  const OutputHistory& history() const { return h_; }
  // Continues the files of a checkpointed run: later frames and rows follow the saved ones.
  void restore(OutputHistory h) { h_ = std::move(h); }

 private:
  const Model<D>& m_;
  std::string dir_;
  OutputHistory h_;
  const std::vector<Recorder<D>>& recorders_;
};

extern template class OutputWriter<2>;
extern template class OutputWriter<3>;

}  // namespace tsuchi
