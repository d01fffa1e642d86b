// Reads a staged model (`steps:`, docs/model-format.md "Analysis steps"). Each step is read as
// a model of its own: the file's sections with the step's analysis, and the boundary and loads
// lists the step gives or, when it gives none, those of the step before (the top-level lists
// before the first step), as Abaqus propagates boundary conditions and loads from step to step.
// Messages name each key where it is in the file (steps[2].analysis.time.end, ...); a problem
// in a part that every step shares is reported once.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <optional>
#include <set>

#include "reader.hpp"

namespace velum::io::model_file {
namespace {

/// Where a step's analysis, boundary and loads come from in the file.
using Origins = std::array<std::pair<std::string, std::string>, 3>;

/// `message` ("name:line: key: text") with a key under analysis, boundary or loads renamed to
/// where that list is in the file.
std::string placed(const std::string& message, const std::string& name, const Origins& origins) {
  if (message.rfind(name, 0) != 0) return message;
  size_t at = name.size();
  if (at < message.size() && message[at] == ':') {
    size_t d = at + 1;
    while (d < message.size() && std::isdigit(static_cast<unsigned char>(message[d]))) ++d;
    if (d > at + 1) at = d;
  }
  if (message.compare(at, 2, ": ") != 0) return message;
  at += 2;
  for (const auto& [from, to] : origins) {
    if (from == to || message.compare(at, from.size(), from) != 0) continue;
    const size_t end = at + from.size();
    if (end < message.size() && (message[end] == '.' || message[end] == '[' || message[end] == ':'))
      return message.substr(0, at) + to + message.substr(end);
  }
  return message;
}

void add_unique(std::vector<std::string>& to, std::set<std::string>& seen, const std::string& m) {
  if (seen.insert(m).second) to.push_back(m);
}

}  // namespace

ModelInput Reader::read_steps(const Node& root) {
  const Node steps = root["steps"];
  if (has(root, "analysis"))
    error(root["analysis"], "analysis",
          "a model with steps gives each step its own analysis (steps[i].analysis): move this "
          "one into the first step");
  if (has(root, "output") && root["output"].IsMap() && root["output"]["checkpoint"])
    error(root["output"]["checkpoint"], "output.checkpoint",
          "a model with steps writes no checkpoints (a staged run cannot be restarted yet)");
  if (!steps.IsSequence() || steps.size() == 0) {
    error(steps, "steps",
          "steps is a list of analysis steps, each {name, analysis, boundary, loads}: give at "
          "least one");
    throw InputError(errors_);
  }

  // The steps' own keys first; then each step's model, with the lists it goes on with.
  struct Plan {
    std::string name;
    int line = 0;
    std::optional<Node> boundary, loads;
    bool boundary_given = false, loads_given = false;
    Origins origins;
  };
  std::vector<Plan> plans;
  std::map<std::string, int> first_line;
  // (emplace rebinds: Node::operator= would write into the node bound.)
  std::optional<Node> boundary, loads;
  if (has(root, "boundary")) boundary.emplace(root["boundary"]);
  if (has(root, "loads")) loads.emplace(root["loads"]);
  std::string boundary_from = "boundary", loads_from = "loads";
  for (size_t i = 0; i < steps.size(); ++i) {
    const Node s = steps[i];
    const std::string p = item("steps", i);
    if (!check_map(s, p, {"name", "analysis", "boundary", "loads"})) continue;
    Plan plan;
    plan.line = line_of(s);
    if (auto name = text(s, "name", p, true)) {
      plan.name = *name;
      if (name->empty())
        error(s["name"], sub(p, "name"), "a step's name must not be empty");
      else if (auto [it, fresh] = first_line.emplace(*name, line_of(s["name"])); !fresh)
        error(s["name"], sub(p, "name"),
              fmt::format("a second step named '{}' (the first is at line {}): step names are "
                          "unique",
                          *name, it->second));
    }
    if (!require(s, "analysis", p)) continue;
    const Node a = s["analysis"];
    if (a.IsMap() && a["type"] && a["type"].IsScalar() && a["type"].Scalar() == "form_finding" &&
        i > 0)
      error(a["type"], sub(p, "analysis.type"),
            "form finding starts from the mesh: only the first step can be form_finding");
    if (a.IsMap() && a["path"])
      error(a["path"], sub(p, "analysis.path"),
            "path following (arc length, displacement control) is not available in steps");
    if (has(s, "boundary")) boundary.emplace(s["boundary"]), boundary_from = sub(p, "boundary");
    if (has(s, "loads")) loads.emplace(s["loads"]), loads_from = sub(p, "loads");
    if (boundary) plan.boundary.emplace(*boundary);
    if (loads) plan.loads.emplace(*loads);
    plan.boundary_given = has(s, "boundary"), plan.loads_given = has(s, "loads");
    plan.origins = {
        {{"analysis", sub(p, "analysis")}, {"boundary", boundary_from}, {"loads", loads_from}}};
    plans.push_back(std::move(plan));
  }
  if (!errors_.empty()) throw InputError(errors_);

  // The model of step i: every top-level section but these, then the step's.
  auto model_of = [&](size_t i) {
    Node m(YAML::NodeType::Map);
    for (const auto& kv : root) {
      const std::string key = kv.first.Scalar();
      if (key != "steps" && key != "analysis" && key != "boundary" && key != "loads")
        m.force_insert(kv.first, kv.second);
    }
    m.force_insert(std::string("analysis"), steps[i]["analysis"]);
    if (plans[i].boundary) m.force_insert(std::string("boundary"), *plans[i].boundary);
    if (plans[i].loads) m.force_insert(std::string("loads"), *plans[i].loads);
    return m;
  };
  std::vector<std::string> errors, warnings;
  std::set<std::string> seen_errors, seen_warnings;
  std::vector<ModelInput::NamedId> part_ids;  // (a part read: every step's)
  std::vector<AnalysisStep> out_steps;
  bool fields = true;
  for (size_t i = 0; i < plans.size(); ++i) {
    Reader r(name_, base_dir_);
    r.step_ = i;  // (a part read: the step's numbering)
    try {
      ModelInput si = r.read_one(model_of(i));
      part_ids.insert(part_ids.end(), si.part_ids.begin(), si.part_ids.end());
      for (const auto& w : si.warnings)
        add_unique(warnings, seen_warnings, placed(w, name_, plans[i].origins));
      AnalysisStep& st = out_steps.emplace_back();
      st.name = plans[i].name, st.line = plans[i].line;
      st.model = std::move(si.model);
      st.analysis = si.analysis;
      st.analysis.time.output_interval = si.output.interval;
      fields = si.output.fields;
      st.boundary_given = plans[i].boundary_given, st.loads_given = plans[i].loads_given;
    } catch (const InputError& e) {
      for (const auto& m : e.messages())
        add_unique(errors, seen_errors, placed(m, name_, plans[i].origins));
    }
  }
  // Each step is held to the limits on steps and output times of a model without steps; the
  // steps together are too (a thousand steps of a million steps each ran without end).
  double total_steps = 0, total_outputs = 0, total_frames = 0;
  for (const AnalysisStep& st : out_steps) {
    const TimeLoopSettings& t = st.analysis.time;
    total_steps += t.t_end / t.step;
    const double outputs = t.output_interval > 0 ? t.t_end / t.output_interval : 0;
    total_outputs += outputs;
    total_frames += fields ? outputs : 0;
  }
  if (!errors.empty()) throw InputError(errors);
  if (total_steps > kMaxSteps)
    error(root["steps"], "steps",
          fmt::format("the steps together take {:.3g} steps (the sum of end / step), more than "
                      "the limit of {:.0e}: give longer steps or fewer analysis steps",
                      total_steps, kMaxSteps));
  if (total_outputs > kMaxOutputTimes || total_frames > kMaxFrames)
    error(root["steps"], "steps",
          fmt::format("the steps together write {:.3g} {} (the sum of end / output.interval), "
                      "more than the limit of {:.0e}: give a longer output.interval or fewer "
                      "analysis steps",
                      fields ? total_frames : total_outputs,
                      fields ? "frames (fields: true)" : "history rows",
                      fields ? kMaxFrames : kMaxOutputTimes));
  if (!errors_.empty()) throw InputError(errors_);
  // The input as a whole is the first step's (its model read once more: the step keeps its own).
  Reader first(name_, base_dir_);
  ModelInput in = first.read_one(model_of(0));
  in.warnings = std::move(warnings);
  in.steps = std::move(out_steps);
  in.part_ids.insert(in.part_ids.end(), part_ids.begin(), part_ids.end());
  return in;
}

}  // namespace velum::io::model_file
