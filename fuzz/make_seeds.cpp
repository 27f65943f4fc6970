// Writes the seed corpora of the fuzz targets:
//   CHECKPOINT_DIR: real checkpoints of the two fuzz models (fuzz_models.hpp), one of the initial
//                   state and one after three steps of a run (with its frames and CSV lengths);
//   INPUT_DIR:      the two fuzz models' input files, one of them with command-line overrides
//                   in the form input_reader_fuzz.cpp reads them.
// The examples' input files are further seeds of the input reader (copied by fuzz/CMakeLists.txt).
#include "fuzz_models.hpp"

#include "tsuchi/io/checkpoint.hpp"
#include "tsuchi/run/simulation.hpp"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>

namespace {

namespace fs = std::filesystem;
using namespace tsuchi;

template <int D>
void checkpoints(const fs::path& dir, const fs::path& scratch) {
  const std::string tag = D == 2 ? "2d" : "3d";
  Model<D> m = fuzz::small_model<D>();
  write_checkpoint<D>((dir / (tag + "_initial.tsuchi")).string(), m, RunProgress{});
  RunOptions o;
  o.output_directory = (scratch / ("run" + tag)).string();
  const RunSummary s = run_simulation<D>(m, fuzz::small_config<D>(), o);
  fs::copy_file(s.checkpoint, dir / (tag + "_step3.tsuchi"), fs::copy_options::overwrite_existing);
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s CHECKPOINT_DIR INPUT_DIR\n", argv[0]);
    return 2;
  }
  try {
    const fs::path ck = argv[1], in = argv[2], scratch = fs::path(argv[1]) / ".." / "seed_runs";
    fs::create_directories(ck);
    fs::create_directories(in);
    fs::create_directories(scratch);
    checkpoints<2>(ck, scratch);
    checkpoints<3>(ck, scratch);
    fs::remove_all(scratch);
    write(in / "fuzz2d.toml", fuzz::kModel2D);
    write(in / "fuzz3d.toml", fuzz::kModel3D);
    write(in / "fuzz2d_overrides.toml",
          fuzz::kModel2D + "\n#%overrides\ntime.end=0.5\nbodies.0.velocity=[1.0, \"sin(y)\"]\nboundary.x_max=\"fixed\"\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
