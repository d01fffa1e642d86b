// Central difference's step in an analysis (march, analysis.cpp): mass scaling at the start,
// then safety x the stable step (capped by time.step) estimated at the start and, from the
// current state, at every trust check (docs/performance.md, explicit dynamics).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "velum/analysis/analysis.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/time/stable_step.hpp"

namespace velum {

class ExplicitStepControl {
 public:
  ExplicitStepControl(MechanicalSystem& sys, const AnalysisSettings& settings,
                      ExplicitStepReport& report, std::function<void(std::string)> warn)
      : sys_(sys), settings_(settings), report_(report), warn_(std::move(warn)) {}
  /// At the start (t, s): mass scaling (ExplicitStepSettings::target_step), then the estimate.
  /// Returns the run's step.
  double start(double t, const State& s);
  /// At a trust check, the state reached by a step of h: the step the run goes on with (the
  /// last one when the settings estimate at the start only). The estimate is made at every
  /// check while it moves, at every second and then every fourth check while it moved less
  /// than 1 % the last time (back to every check once it moves more than 2 %).
  double update(double t, double h, const State& s, double last_step);
  /// What a restart needs (the estimate's vector, the mass added) appended to m; read back
  /// from m[at...] at a restart (the mass added applied again). Collective calls.
  void save(std::vector<double>& m) const;
  void restore(const std::vector<double>& m, size_t at);

 private:
  double set_step(double estimate);
  void scale_mass();

  MechanicalSystem& sys_;
  const AnalysisSettings& settings_;
  ExplicitStepReport& report_;
  std::function<void(std::string)> warn_;
  StableStepEstimate estimate_;
  VecX added_;  ///< mass scaling: the mass added per node (empty: none)
  static constexpr int kMaxStride = 4;
  int stride_ = 1, since_ = 0;  ///< estimate every stride_ checks; checks since the last
};

}  // namespace velum
