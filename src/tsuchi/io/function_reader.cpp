#include "tsuchi/io/function_reader.hpp"

#include "tsuchi/io/csv_table.hpp"

#include <cctype>

namespace tsuchi::io {

namespace {

// Times strictly increasing: a table is a function of time, and the integral of a record (a base
// acceleration to a velocity) is not defined over a step backwards.
void check_increasing(const std::vector<double>& t, const std::function<void(std::size_t)>& fail) {
  for (std::size_t k = 1; k < t.size(); ++k)
    if (!(t[k] > t[k - 1])) fail(k);
}

TimeFunction read_table(Section& s) {
  const toml::node& n = s.need("table", "an array of [t, value] pairs");
  const std::string expected = "an array of [t (s), value] pairs with t increasing";
  auto a = n.as_array();
  if (!a || a->empty()) s.fail("table", fmt::format("expected {}, got {}", expected, a ? "an empty array" : describe(n)));
  std::vector<double> t, v;
  for (std::size_t k = 0; k < a->size(); ++k) {
    auto pair = a->get(k)->as_array();
    if (!pair || pair->size() != 2)
      s.fail("table", fmt::format("expected {}, got {} in entry {}", expected, describe(*a->get(k)), k));
    t.push_back(s.number_of("table", *pair->get(0), expected));
    v.push_back(s.number_of("table", *pair->get(1), expected));
  }
  check_increasing(t, [&](std::size_t k) {
    s.fail("table", fmt::format("expected times increasing, got t = {} in entry {} after t = {} in entry {}", t[k], k,
                                t[k - 1], k - 1));
  });
  return TimeFunction::table(std::move(t), std::move(v));
}

TimeFunction read_record(Section& s, Config& c) {
  const std::string file = s.string("file", "a CSV file of a time column and a value column");
  const std::string context = s.located("file", "").substr(0, s.located("file", "").size() - 2);
  const CsvTable csv = read_csv_table(file, input_directory(c.source), context);
  std::array<std::string, 2> names{csv.names.size() > 0 ? csv.names[0] : "", csv.names.size() > 1 ? csv.names[1] : ""};
  if (const toml::node* n = s.get("columns")) {
    auto a = n->as_array();
    const std::string expected = "an array of two column names, [time, value]";
    if (!a || a->size() != 2 || !a->get(0)->is_string() || !a->get(1)->is_string())
      s.fail("columns", fmt::format("expected {}, got {}", expected, describe(*n)));
    names = {a->get(0)->as_string()->get(), a->get(1)->as_string()->get()};
  } else if (csv.names.size() < 2) {
    s.fail("file", fmt::format("\"{}\" has one column (\"{}\"); expected a time column and a value column", csv.file,
                               csv.names[0]));
  }
  std::array<int, 2> col{};
  for (int k = 0; k < 2; ++k) {
    col[static_cast<std::size_t>(k)] = csv.column(names[static_cast<std::size_t>(k)]);
    if (col[static_cast<std::size_t>(k)] < 0)
      s.fail("columns", fmt::format("\"{}\" has no column \"{}\"; its columns are {}", csv.file,
                                    names[static_cast<std::size_t>(k)], quoted_list(csv.names)));
  }
  const double scale = s.number("scale", "a finite factor on the values", any, 1.0);
  const double time_scale = s.number("time_scale", "a positive factor on the times", positive, 1.0);
  std::vector<double> t, v;
  for (const auto& row : csv.rows) {
    t.push_back(time_scale * row[static_cast<std::size_t>(col[0])]);
    v.push_back(scale * row[static_cast<std::size_t>(col[1])]);
  }
  check_increasing(t, [&](std::size_t k) {
    s.fail("file", fmt::format("{}: expected times increasing in column \"{}\", got {} after {}", csv.at(k), names[0],
                               csv.rows[k][static_cast<std::size_t>(col[0])], csv.rows[k - 1][static_cast<std::size_t>(col[0])]));
  });
  c.file_digests.push_back(csv.digest);
  c.data_files.push_back({csv.file, context});
  return TimeFunction::table(std::move(t), std::move(v));
}

}  // namespace

void read_functions(Section& top, Config& c) {
  const auto tables = top.tables("functions");
  for (std::size_t i = 0; i < tables.size(); ++i) {
    Section s(*tables[i], fmt::format("functions.{}", i), top.file());
    FunctionConfig f;
    f.name = s.string("name", "a function name");
    for (const auto& other : c.functions)
      if (other.name == f.name) s.fail("name", fmt::format("function \"{}\" is defined twice", f.name));
    const int given = s.has("table") + s.has("formula") + s.has("file");
    if (given != 1)
      s.fail_one_of({"table", "formula", "file"},
                    "give exactly one of 'table' ([[t, value], ...]), 'formula' (an expression of t in quotes) and "
                    "'file' (a CSV record)");
    if (s.has("table")) {
      f.f = read_table(s);
    } else if (s.has("formula")) {
      const std::string text = s.string("formula", "an expression of t in quotes, e.g. \"min(t / 2, 1)\"");
      try {
        f.f = TimeFunction::formula(std::make_shared<const Expression>(text, Expression::Of::Time), f.name, printable(text));
      } catch (const std::invalid_argument& e) {
        s.fail("formula", fmt::format("\"{}\" is not a valid formula of t: {}", printable(text), e.what()));
      }
    } else {
      f.f = read_record(s, c);
    }
    s.finish();
    f.unused_warning = s.located("name", fmt::format("function \"{}\" is defined but nothing names it (as "
                                                     "gravity_function, prescribed_velocity_function or function)",
                                                     printable(f.name)));
    c.functions.push_back(std::move(f));
  }
}

int read_function_ref(Section& s, std::string_view key, const Config& c) {
  if (!s.has(key)) return -1;
  const std::string name = s.string(key, "the name of a function of [[functions]]");
  for (std::size_t k = 0; k < c.functions.size(); ++k)
    if (c.functions[k].name == name) {
      c.functions[k].named = true;
      return static_cast<int>(k);
    }
  s.fail(key, fmt::format("expected the name of a function of [[functions]] ({}), got \"{}\"",
                          c.functions.empty() ? std::string("none defined") : quoted_list(c.functions, &FunctionConfig::name),
                          printable(name)));
}

}  // namespace tsuchi::io
