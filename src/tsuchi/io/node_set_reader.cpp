#include "tsuchi/io/node_set_reader.hpp"

#include "tsuchi/io/function_reader.hpp"

namespace tsuchi::io {

namespace {

// velocity = {x = 0.1} or acceleration = {x = 1.0}: the components given are driven.
void read_components(Section& s, std::string_view key, const std::string& unit, int dim, NodeSetConfig& ns) {
  const toml::table* t = s.table(key);
  Section v(*t, s.key_path(key), s.file());
  if (dim == 2 && v.has("z"))
    v.fail("z", "expected a key of the x or y axis: model.dimension is 2 (plane strain), which has no z axis");
  bool any_given = false;
  for (int d = 0; d < dim; ++d) {
    if (!v.has(axis_name[d])) continue;
    ns.driven[d] = any_given = true;
    ns.value[d] = v.number(axis_name[d], unit, any);
  }
  v.finish();
  if (!any_given)
    s.fail(key, fmt::format("expected at least one component, e.g. {} = {{ x = 1.0 }}, got an empty table", key));
}

}  // namespace

void read_node_set_motion(Section& s, const Config& c, NodeSetConfig& ns) {
  const int dim = c.dimension;
  if (s.has("name")) {
    ns.name = s.one_line("name", "a node-set name");
    if (ns.name.empty()) s.fail("name", "expected a non-empty node-set name");
    // Names defined twice: read_boundary, which sees every set.
  } else {
    s.get("name");
  }
  if (s.has("velocity") && s.has("acceleration"))
    s.fail("acceleration", "expected either 'velocity' or 'acceleration' for one node set, not both: a velocity "
                           "history fixes the acceleration and the other way round");
  if (s.has("velocity")) {
    ns.drive = NodeSetConfig::Drive::Velocity;
    read_components(s, "velocity", "a velocity in m/s", dim, ns);
  } else if (s.has("acceleration")) {
    ns.drive = NodeSetConfig::Drive::Acceleration;
    read_components(s, "acceleration", "an acceleration in m/s^2", dim, ns);
  } else {
    s.get("velocity"), s.get("acceleration");
  }
  if (ns.drive == NodeSetConfig::Drive::None) {
    for (const char* key : {"function", "initial_velocity"})
      if (s.has(key))
        s.fail(key, fmt::format("expected 'velocity' or 'acceleration' with '{}': it scales a driven motion, and "
                                "this set drives nothing", key));
  }
  ns.function = read_function_ref(s, "function", c);
  if (s.has("initial_velocity")) {
    if (ns.drive != NodeSetConfig::Drive::Acceleration)
      s.fail("initial_velocity", "expected 'acceleration' with 'initial_velocity': a velocity history gives the "
                                 "velocity at t = 0 itself");
    const toml::table* t = s.table("initial_velocity");
    Section v(*t, s.key_path("initial_velocity"), s.file());
    for (int d = 0; d < dim; ++d) {
      if (!v.has(axis_name[d])) continue;
      if (!ns.driven[d])
        v.fail(axis_name[d], fmt::format("expected a component of 'acceleration': {} is not driven", axis_name[d]));
      ns.initial_velocity[d] = v.number(axis_name[d], "a velocity in m/s", any);
    }
    v.finish();
  } else {
    s.get("initial_velocity");
  }
  bool holds = false;
  for (int d = 0; d < dim; ++d) {
    holds = holds || ns.fix[d] || ns.driven[d];
    if (ns.fix[d] && ns.driven[d])
      s.fail("fix", fmt::format("component {} is both fixed and driven ({}.{}) in this node set; expected each "
                                "component held one way (remove it from 'fix', or from '{}')",
                                axis_name[d], ns.drive == NodeSetConfig::Drive::Velocity ? "velocity" : "acceleration",
                                axis_name[d], ns.drive == NodeSetConfig::Drive::Velocity ? "velocity" : "acceleration"));
  }
  if (!holds)
    s.fail_here("expected 'fix' (components held at zero) and/or 'velocity' or 'acceleration' (driven components): "
                "this node set holds nothing");
}

}  // namespace tsuchi::io
