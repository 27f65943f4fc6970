#include "tsuchi/io/stage_reader.hpp"

#include "tsuchi/io/csv_table.hpp"
#include "tsuchi/io/shape_reader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace tsuchi::io {

namespace {

// What a stage may change, per table it merges in; the rest is fixed when the model is made.
const std::set<std::string> model_keys = {"gravity", "gravity_function"};
const std::set<std::string> time_keys = {"courant", "dt"};
const std::set<std::string> body_keys = {"material", "prescribed_velocity", "prescribed_velocity_function",
                                         "prescribed_velocity_gradient"};
// The stage's own keys (read by read_stage) and the tables it merges into the input's.
const std::set<std::string> own_keys = {"name", "duration", "steps", "max_steps", "unbalanced_force_ratio",
                                        "kinetic_energy_ratio", "at_rest", "recorder", "above", "below", "remove", "add",
                                        "reset_displacements"};
const std::set<std::string> merged_keys = {"model", "solver", "time", "boundary", "loads", "contact", "materials",
                                           "bodies"};

std::string list(const std::set<std::string>& keys) { return quoted_list(keys); }

const toml::array& stage_array(const toml::table& root) { return *root.get_as<toml::array>("stages"); }

// Tables merge key by key; anything else (numbers, strings, arrays) replaces.
void merge(toml::table& into, toml::table&& from) {
  for (auto&& [k, v] : from) {
    toml::table* dst = into.get_as<toml::table>(k.str());
    if (dst && v.is_table()) {
      merge(*dst, std::move(*v.as_table()));
      continue;
    }
    const toml::key& k_ = k;  // clang 14 cannot capture a structured binding
    v.visit([&](auto&& value) { into.insert_or_assign(k_, std::move(value)); });  // the key keeps its place in the file
  }
}

// The [[materials]] or [[bodies]] table called `name` ("bodyN" when a body has no name).
toml::table* named(toml::table& root, std::string_view array, const std::string& name) {
  auto* a = root.get_as<toml::array>(array);
  if (!a) return nullptr;
  for (std::size_t i = 0; i < a->size(); ++i) {
    auto* t = a->get(i)->as_table();
    if (!t) continue;
    const auto* n = t->get_as<std::string>("name");
    const std::string own = n ? n->get() : (array == "bodies" ? fmt::format("body{}", i) : std::string{});
    if (own == name) return t;
  }
  return nullptr;
}

std::string names_of(const toml::table& root, std::string_view array) {
  std::vector<std::string> names;
  if (const auto* a = root.get_as<toml::array>(array))
    for (std::size_t i = 0; i < a->size(); ++i)
      if (const auto* t = a->get(i)->as_table()) {
        const auto* n = t->get_as<std::string>("name");
        names.push_back(n ? n->get() : fmt::format("body{}", i));
      }
  return quoted_list(names);
}

// A stage's table of changes to named materials or bodies: each entry a table naming one of them.
void merge_named(toml::table& root, toml::table& stage, Section& s, std::string_view key,
                 const std::set<std::string>* allowed) {
  toml::table* changes = stage.get_as<toml::table>(key);
  if (!changes) s.fail(key, fmt::format("expected a table of changes by {} name ([stages.{}.NAME]), got {}",
                                        key == "bodies" ? "body" : "material", key, describe(*stage.get(key))));
  for (auto&& [name, v] : *changes) {
    Section entry(*changes, s.key_path(key), s.file());
    const std::string n(name.str());
    auto* change = v.as_table();
    if (!change) entry.fail(n, fmt::format("expected a table of the {}'s keys to change, got {}",
                                           key == "bodies" ? "body" : "material", describe(v)));
    toml::table* target = named(root, key, n);
    if (!target)
      entry.fail(n, fmt::format("expected the name of one of the input's {} ({}), got \"{}\"", key,
                                names_of(root, key), printable(n)));
    for (auto&& [k, kv] : *change) {
      Section c(*change, entry.key_path(n), s.file());
      if (k.str() == "name")
        c.fail("name", "a stage cannot rename; the table's key names what it changes");
      if (allowed && !allowed->count(std::string(k.str())))
        c.fail(k.str(), fmt::format("a stage may change a body's {}; the rest is fixed when the body is made",
                                    list(*allowed)));
    }
    // A body's motion keys are replaced whole, so that `prescribed_velocity = {}` frees the body;
    // a material's keys are values anyway.
    if (allowed) {
      for (auto&& [k, kv] : *change) {
        const toml::key& k_ = k;
        kv.visit([&](auto&& value) { target->insert_or_assign(k_, std::move(value)); });
      }
    } else if (change->contains("model")) {
      // Another model: its own keys, not the old one's (a Mohr-Coulomb cohesion would be unknown
      // to an elastic model); the name stays.
      toml::table fresh;
      fresh.insert("name", n);
      for (auto&& [k, kv] : *change) {
        const toml::key& k_ = k;
        kv.visit([&](auto&& value) { fresh.insert_or_assign(k_, std::move(value)); });
      }
      *target = std::move(fresh);
    } else {
      merge(*target, std::move(*change));
    }
  }
}

}  // namespace

std::size_t stage_count(const toml::table& root, const std::string& file) {
  const toml::node* n = root.get("stages");
  if (!n) return 0;
  Section top(root, "", file);
  const auto tables = top.tables("stages");
  if (tables.empty()) top.fail("stages", "expected at least one [[stages]] table, got an empty array");
  return tables.size();
}

toml::table merge_stages(toml::table root, std::size_t last, const std::string& file) {
  toml::array stages = std::move(*root.get_as<toml::array>("stages"));
  root.erase("stages");
  for (std::size_t k = 0; k <= last; ++k) {
    toml::table& stage = *stages.get(k)->as_table();
    Section s(stage, fmt::format("stages.{}", k), file);
    for (auto&& [key, v] : stage) {
      const std::string name(key.str());
      if (own_keys.count(name)) continue;
      if (!merged_keys.count(name))
        throw InputError(fmt::format("{}: unknown key '{}': a stage has {} and changes {}{}", where(file, key.source()),
                                     s.key_path(name), list(own_keys), list(merged_keys), ""));
    }
    for (const auto& [name, allowed] : {std::pair{"model", &model_keys}, std::pair{"time", &time_keys}}) {
      const toml::node* n = stage.get(name);
      if (!n) continue;
      if (!n->is_table()) s.fail(name, fmt::format("expected a table ([stages.{}]), got {}", name, describe(*n)));
      for (auto&& [key, v] : *n->as_table()) {
        Section t(*n->as_table(), s.key_path(name), file);
        if (!allowed->count(std::string(key.str())))
          t.fail(key.str(), fmt::format("a stage may change {} of [{}]; the rest holds for the whole run", list(*allowed),
                                      name));
      }
    }
    if (const toml::node* n = stage.get("solver"); n && n->is_table() && n->as_table()->contains("velocity_transfer"))
      Section(*n->as_table(), s.key_path("solver"), file)
          .fail("velocity_transfer", "the velocity transfer holds for the whole run (APIC particles carry a matrix FLIP ones do not)");
    if (stage.contains("materials")) merge_named(root, stage, s, "materials", nullptr);
    if (stage.contains("bodies")) merge_named(root, stage, s, "bodies", &body_keys);
    // dt and courant are one choice: the stage's replaces the input's.
    if (const auto* t = stage.get_as<toml::table>("time"); t && root.get_as<toml::table>("time")) {
      if (t->contains("dt")) root.get_as<toml::table>("time")->erase("courant");
      if (t->contains("courant")) root.get_as<toml::table>("time")->erase("dt");
    }
    for (const char* name : {"model", "solver", "time", "boundary", "loads", "contact"}) {
      toml::node* n = stage.get(name);
      if (!n) continue;
      if (toml::table* t = n->as_table(); t && root.get_as<toml::table>(name)) merge(*root.get_as<toml::table>(name), std::move(*t));
      else n->visit([&](auto&& value) { root.insert_or_assign(name, std::move(value)); });
    }
  }
  return root;
}

StageConfig read_stage(const toml::table& root, std::size_t k, Config& during, const std::string& file) {
  const toml::table& t = *stage_array(root).get(k)->as_table();
  Section s(t, fmt::format("stages.{}", k), file);
  StageConfig st;
  st.where = where(file, t.source());
  st.name = s.one_line("name", "a name for the stage", fmt::format("stage{}", k + 1));
  StageEnd& e = st.end;
  const auto above_zero = [](double x) { return x > 0.0; };
  const auto ratio = [](double x) { return x > 0.0 && x < 1.0; };
  e.duration = s.optional_number("duration", "a positive time in s", above_zero);
  e.steps = s.integer("steps", "a positive whole number of steps", [](std::int64_t n) { return n > 0; }, 0);
  e.max_steps = s.integer("max_steps", "a positive whole number of steps", [](std::int64_t n) { return n > 0; }, 0);
  e.unbalanced_force_ratio = s.optional_number("unbalanced_force_ratio", "a tolerance in (0, 1)", ratio);
  e.kinetic_energy_ratio = s.optional_number("kinetic_energy_ratio", "a tolerance in (0, 1)", ratio);
  e.at_rest = s.boolean("at_rest", true);
  if (s.has("at_rest") && !e.equilibrium())
    s.fail("at_rest", "ends an equilibrium stage on its ground at rest, but the stage asks for no equilibrium "
                      "('unbalanced_force_ratio' or 'kinetic_energy_ratio')");
  if (s.has("recorder")) {
    const std::string name = s.string("recorder", "the name of a recorder");
    const auto it = std::find_if(during.recorders.begin(), during.recorders.end(),
                                 [&](const RecorderConfig& r) { return r.name == name; });
    if (it == during.recorders.end())
      s.fail("recorder", fmt::format("expected the name of a recorder ({}), got \"{}\"",
                                     during.recorders.empty() ? std::string("none defined")
                                                              : quoted_list(during.recorders, &RecorderConfig::name),
                                     printable(name)));
    e.recorder = static_cast<int>(it - during.recorders.begin());
    e.above = s.optional_number("above", "the value at which the stage ends", [](double) { return true; });
    e.below = s.optional_number("below", "the value at which the stage ends", [](double) { return true; });
    if (!e.above && !e.below) s.need("above", "'above' and/or 'below': the recorder's value that ends the stage");
  } else {
    for (const char* key : {"above", "below"})
      if (s.has(key)) s.fail(key, "bounds the value of the stage's 'recorder', but the stage names none");
  }
  if (!e.duration && e.steps == 0 && !e.equilibrium() && e.recorder < 0)
    s.need("duration", "an end for the stage: 'duration' (s), 'steps', 'unbalanced_force_ratio' and/or "
                       "'kinetic_energy_ratio' (equilibrium), or 'recorder' with 'above' or 'below'");
  if (!e.duration && e.steps == 0 && e.max_steps == 0)
    s.need("max_steps", fmt::format("a step limit: a stage that ends by {} may never get there",
                                    e.equilibrium() ? "equilibrium" : "a recorder's value"));
  const auto body_index = [&](Section& at, const char* key, const std::string& name, const std::string& expected) {
    const auto it = std::find_if(during.bodies.begin(), during.bodies.end(),
                                 [&](const BodyConfig& b) { return b.name == name; });
    if (it == during.bodies.end())
      at.fail(key, fmt::format("expected {} ({}), got \"{}\"", expected, quoted_list(during.bodies, &BodyConfig::name),
                               printable(name)));
    return static_cast<int>(it - during.bodies.begin());
  };
  // A part by its shape: { body = "NAME" or ["NAME", ...], shape = ..., and the shape's keys }.
  const auto region = [&](const char* key, std::size_t j, const toml::table& entry) {
    Section rs(entry, fmt::format("{}.{}", s.key_path(key), j), file);
    StageRegionConfig r;
    r.key_path = rs.path();
    r.where = where(file, entry.source());
    const bool adding = std::string_view(key) == "add";
    const std::string expected_body =
        adding ? "the name of a body that a stage adds" : "the name of a body";
    if (const toml::node* b = rs.get("body")) {
      if (const auto* name = b->as_string()) {
        r.bodies.push_back(body_index(rs, "body", name->get(), expected_body));
      } else if (const auto* a = b->as_array(); a && !a->empty()) {
        for (const auto& v : *a) {
          const auto* n = v.as_string();
          if (!n) rs.fail("body", fmt::format("expected body names, got an entry that is {}", describe(v)));
          const int i = body_index(rs, "body", n->get(), expected_body);
          if (std::find(r.bodies.begin(), r.bodies.end(), i) != r.bodies.end())
            rs.fail("body", fmt::format("body \"{}\" is named twice", n->get()));
          r.bodies.push_back(i);
        }
      } else {
        rs.fail("body", fmt::format("expected a body name or an array of body names, got {}", describe(*b)));
      }
    } else if (adding) {
      rs.need("body", "the body whose particles the region adds (a body named in regions of 'add' waits "
                      "until they add its parts)");
    }
    for (const int b : r.bodies)
      if (during.bodies[static_cast<std::size_t>(b)].rigid_mass > 0.0)
        rs.fail("body", fmt::format("body \"{}\" is a rigid body (rigid_mass): it is {} whole, by its name in '{}'",
                                    during.bodies[static_cast<std::size_t>(b)].name, adding ? "added" : "removed", key));
    r.kind = shape_kind(rs);
    // A half-space alone may bound a cut ("everything of the ground above y = 8 m").
    r.shape = read_shape(rs, during.dimension, input_directory(file), Extent::MayBeUnbounded, &during.data_files,
                         &during.warnings);
    rs.finish();
    (adding ? st.add_regions : st.remove_regions).push_back(std::move(r));
  };
  auto bodies = [&](const char* key, std::vector<int>& out) {
    const toml::node* n = s.get(key);
    if (!n) return;
    const auto* a = n->as_array();
    const std::string expected = "an array of body names and of regions ({ body = \"NAME\", shape keys })";
    if (!a) s.fail(key, fmt::format("expected {}, got {}", expected, describe(*n)));
    for (std::size_t j = 0; j < a->size(); ++j) {
      const toml::node& v = *a->get(j);
      if (const auto* entry = v.as_table()) {
        region(key, j, *entry);
        continue;
      }
      const auto* name = v.as_string();
      if (!name) s.fail(key, fmt::format("expected {}, got an entry that is {}", expected, describe(v)));
      const int b = body_index(s, key, name->get(), "the name of a body");
      if (std::find(out.begin(), out.end(), b) != out.end())
        s.fail(key, fmt::format("body \"{}\" is named twice", name->get()));
      out.push_back(b);
    }
  };
  bodies("remove", st.remove);
  bodies("add", st.add);
  for (const char* key : {"remove", "add"})
    if (k == 0 && s.has(key))
      s.fail(key, fmt::format("expected no '{}' in the first stage: the model starts with the bodies that have no 'add'; "
                              "a body to dig out later is removed by a later stage", key));
  for (const int b : st.remove)
    if (std::find(st.add.begin(), st.add.end(), b) != st.add.end())
      s.fail("add", fmt::format("body \"{}\" is both removed and added by this stage",
                                during.bodies[static_cast<std::size_t>(b)].name));
  st.reset_displacements = s.boolean("reset_displacements", false);
  if (k == 0 && st.reset_displacements)
    s.fail("reset_displacements", "expected no reset in the first stage: nothing has moved before it");
  // What the stage changes (merge_stages has checked the tables).
  for (const char* key : {"model", "solver", "time", "boundary", "loads", "contact", "materials", "bodies"}) s.get(key);
  if (const auto* m = t.get_as<toml::table>("model")) {
    st.changes_gravity = m->contains("gravity") || m->contains("gravity_function");
    st.sets_gravity_function = m->contains("gravity_function");
  }
  if (const auto* b = t.get_as<toml::table>("boundary")) st.sets_node_sets = b->contains("nodes");
  st.changes_loads = t.contains("loads");
  st.changes_contact = t.contains("contact");
  st.changes_boundary = t.contains("boundary");
  st.changes_materials = t.contains("materials");
  st.changes_solver = t.contains("solver");
  if (const auto* b = t.get_as<toml::table>("bodies"))
    for (auto&& [name, v] : *b)
      for (std::size_t i = 0; i < during.bodies.size(); ++i) {
        if (during.bodies[i].name != name.str() || !v.is_table()) continue;
        const auto& keys = *v.as_table();
        if (keys.contains("material")) st.changes_body_material.push_back(static_cast<int>(i));
        if (keys.size() > (keys.contains("material") ? 1u : 0u)) st.changes_motion.push_back(static_cast<int>(i));
      }
  s.finish();
  return st;
}

void check_stage_sequence(Config& c, const toml::table& root) {
  const std::size_t n = c.bodies.size();
  c.body_starts_dormant.assign(n, false);
  for (const auto& st : c.stages) {
    for (const int b : st.add) c.body_starts_dormant[static_cast<std::size_t>(b)] = true;
    for (const auto& r : st.add_regions)
      for (const int b : r.bodies) c.body_starts_dormant[static_cast<std::size_t>(b)] = true;
  }
  // Waiting whole, partly added by regions, there whole (perhaps cut by regions), removed whole.
  enum class State { Waiting, Partial, Whole, Removed };
  std::vector<State> state(n);
  for (std::size_t b = 0; b < n; ++b) state[b] = c.body_starts_dormant[b] ? State::Waiting : State::Whole;
  const auto there = [&](std::size_t b) { return state[b] == State::Partial || state[b] == State::Whole; };
  for (std::size_t k = 0; k < c.stages.size(); ++k) {
    const StageConfig& st = c.stages[k];
    Section s(*stage_array(root).get(k)->as_table(), fmt::format("stages.{}", k), c.source);
    for (std::size_t j = 0; j < k; ++j)
      if (c.stages[j].name == st.name) s.fail("name", fmt::format("stage \"{}\" is defined twice", st.name));
    const auto absent = [&](std::size_t b) {
      return fmt::format("body \"{}\" is not there in stage \"{}\": {}", c.bodies[b].name, st.name,
                         state[b] == State::Removed ? "an earlier stage removed it" : "a later stage adds it");
    };
    // In the order change_particles applies them: removals, then additions.
    for (const auto& r : st.remove_regions)
      for (const int b : r.bodies)
        if (!there(static_cast<std::size_t>(b))) throw InputError(fmt::format("{}: key '{}.body': {}", r.where, r.key_path, absent(static_cast<std::size_t>(b))));
    for (const int b : st.remove) {
      const auto ub = static_cast<std::size_t>(b);
      if (!there(ub)) s.fail("remove", absent(ub));
      state[ub] = State::Removed;
    }
    for (const int b : st.add) {
      const auto ub = static_cast<std::size_t>(b);
      if (!(state[ub] == State::Waiting || state[ub] == State::Partial))
        s.fail("add", fmt::format("body \"{}\" {}; a body is added once, by the first stage that names it in 'add' "
                                  "(after any parts that regions add), and is absent until then",
                                  c.bodies[ub].name,
                                  state[ub] == State::Removed ? "was removed by an earlier stage" : "is added by an earlier stage"));
      state[ub] = State::Whole;
    }
    for (const auto& r : st.add_regions)
      for (const int b : r.bodies) {
        const auto ub = static_cast<std::size_t>(b);
        if (state[ub] == State::Whole || state[ub] == State::Removed)
          throw InputError(fmt::format(
              "{}: key '{}.body': body \"{}\" {}: a region adds particles of a body that still waits (a body "
              "named in a region of 'add' is absent from the start, until its parts are added)",
              r.where, r.key_path, c.bodies[ub].name,
              state[ub] == State::Removed ? "was removed by an earlier stage"
              : std::find(st.add.begin(), st.add.end(), b) != st.add.end() ? "is added whole by this stage"
                                                                            : "was added whole by an earlier stage"));
        state[ub] = State::Partial;
      }
    if (!st.remove.empty() && std::none_of(state.begin(), state.end(), [](State x) { return x == State::Partial || x == State::Whole; }))
      s.fail("remove", fmt::format("stage \"{}\" removes every body there is: it would run on an empty model; "
                                   "expected at least one body left",
                                   st.name));
  }
  if (std::none_of(c.body_starts_dormant.begin(), c.body_starts_dormant.end(), [](bool d) { return !d; }))
    Section(root, "", c.source)
        .fail("stages", "expected a body present from the start: every body is added by a stage");
}

void read_fos(Section& s, Config& c) {
  FosConfig& f = c.fos;
  f.given = true;
  if (s.has("stage")) {
    const std::string name = s.string("stage", "the name of a stage");
    const auto it = std::find_if(c.stages.begin(), c.stages.end(), [&](const StageConfig& st) { return st.name == name; });
    if (it == c.stages.end())
      s.fail("stage", fmt::format("expected the name of a stage ({}), got \"{}\"",
                                  c.stages.empty() ? std::string("the input has no [[stages]]")
                                                   : quoted_list(c.stages, &StageConfig::name),
                                  printable(name)));
    f.after_stage = static_cast<int>(it - c.stages.begin());
  } else if (c.staged()) {
    f.after_stage = static_cast<int>(c.stages.size()) - 1;
  }
  f.reduce_dilatancy = s.boolean("reduce_dilatancy", false);
  if (const toml::node* n = s.get("bracket")) {
    const Triple b = s.vector_of("bracket", *n, 2, "two factors, 0 < lower < upper", [](double x) { return x > 0.0; });
    if (!(b[0] < b[1])) s.fail("bracket", fmt::format("expected lower < upper, got [{}, {}]", b[0], b[1]));
    f.lower = b[0], f.upper = b[1];
  }
  f.tolerance = s.number("tolerance", "a relative width in (0, 1)", [](double x) { return x > 0.0 && x < 1.0; }, 0.01);
  f.max_steps = s.integer("max_steps",
                          fmt::format("a whole number of steps per trial of at least {}: a trial's ratio is judged "
                                      "from its 20th step and its rest over its last fifth",
                                      FosConfig::min_steps),
                          [](std::int64_t n) { return n >= FosConfig::min_steps; }, 0);
  if (f.max_steps == 0) s.need("max_steps", "the most steps a trial may take to reach equilibrium; without it, a trial is a failure");
  f.unbalanced_force_ratio = s.number("unbalanced_force_ratio", "a tolerance in (0, 1)",
                                      [](double x) { return x > 0.0 && x < 1.0; }, 1e-3);
  f.displacement_limit = s.optional_number("displacement_limit", "a positive displacement in m", [](double x) { return x > 0.0; });
  f.extend = s.integer("extend", "a whole number from 1 to 100: the most budget, in multiples of max_steps, that a "
                                 "trial still slowing down may take",
                       [](std::int64_t n) { return n >= 1 && n <= 100; }, 4);
  f.trials_at_once = static_cast<int>(s.integer("trials_at_once", "a whole number from 1 to 64",
                                                [](std::int64_t n) { return n >= 1 && n <= 64; }, 2));
  s.finish();
}

}  // namespace tsuchi::io
