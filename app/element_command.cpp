#include "element_command.hpp"
#include "console.hpp"

#include "tsuchi/core/version.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/element/element_csv.hpp"
#include "tsuchi/element/element_driver.hpp"
#include "tsuchi/io/atomic_file.hpp"
#include "tsuchi/io/element_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>

namespace tsuchi::app {

namespace {

namespace fs = std::filesystem;
using element::ElementRow;

std::string output_path(const ElementOptions& o) {
  if (!o.output.empty()) return o.output;
  return fs::path(o.file).stem().string() + ".csv";
}

// Writing the CSV over the input by a slip of -o would destroy the input.
void refuse_overwriting_input(const std::string& input, const std::string& output) {
  std::error_code e1, e2;
  const fs::path a = fs::weakly_canonical(input, e1), b = fs::weakly_canonical(output, e2);
  if (!e1 && !e2 && a == b)
    throw InputError(fmt::format("{}: the output file {} is the input file itself; give another with -o", input, output));
}

std::string kpa(double pa) { return fmt::format("{:.5g} kPa", pa / 1e3); }

}  // namespace

int run_element_command(const ElementOptions& o) {
  const io::ElementInput in = io::read_element_file(o.file, o.overrides);
  for (const auto& w : in.warnings) say(stderr, "warning: {}\n", w);
  const std::string out = output_path(o);
  refuse_overwriting_input(o.file, out);
  refuse_unless_regular_file(out, "the output file");  // -o /dev/full would be replaced by a file
  if (const fs::path dir = fs::path(out).parent_path(); !dir.empty()) prepare_output_directory(dir.string());

  const std::string material = io::describe_material(in.material);
  if (!o.quiet) {
    say("element    {}{}\n", in.source, in.title.empty() ? "" : fmt::format(" ({})", in.title));
    say("material   {}\n", material);
    say("path       {}\n", in.path.description);
    say("output     {} ({} rows)\n", out, in.path.total_increments() + 1);
  }

  std::vector<ElementRow> rows;
  rows.reserve(static_cast<std::size_t>(in.path.total_increments()) + 1);
  std::string failure;
  try {
    element::drive_element(in.material, in.path, in.iteration, [&](const ElementRow& r) { rows.push_back(r); });
  } catch (const RunError& e) {
    failure = e.what();
  }

  std::vector<std::string> notes{fmt::format("tsuchi {} element {}{}", version, in.source,
                                             in.title.empty() ? "" : fmt::format(" ({})", in.title)),
                                 fmt::format("material {}", material), fmt::format("path: {}", in.path.description),
                                 fmt::format("stress control converged to {:g} of the stress scale",
                                             in.iteration.tolerance)};
  if (!failure.empty()) notes.push_back(fmt::format("STOPPED: {}", failure));
  write_file_atomically(out, element::format_csv(rows, notes));
  if (!failure.empty())
    throw RunError(fmt::format("{}\n{} rows (the initial state and increments 1 to {}) are in {}", failure,
                               rows.size(), rows.back().increment, out));

  // A perfectly plastic curve is flat after its peak, up to round-off: report where the peak is
  // first reached, not the row that happens to be largest in the last digits.
  const auto peak = [&](auto value) {
    double top = value(rows.front());
    for (const auto& r : rows) top = std::max(top, value(r));
    const auto first = std::find_if(rows.begin(), rows.end(),
                                    [&](const ElementRow& r) { return value(r) >= top - 1e-6 * std::abs(top); });
    return std::pair{top, first->increment};
  };
  const auto [q, q_at] = peak([](const ElementRow& r) { return r.q(); });
  const auto [d, d_at] = peak([](const ElementRow& r) { return r.deviator(); });
  say("peak       q = {} (first reached at increment {}), deviator = {} (increment {})\n", kpa(q), q_at,
             kpa(d), d_at);
  say("done: {} rows in {}\n", rows.size(), out);
  return exit_code::ok;
}

}  // namespace tsuchi::app
