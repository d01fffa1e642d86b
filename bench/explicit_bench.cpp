// Explicit dynamics at the hardware's pace (issue 46): a central-difference run of an n x n
// pressurised, prestressed square sheet (quad4, or tri3 with each quad split in two; the
// tension field on or off) through run_analysis, trust checks included, for a given number of
// steps. The figure is element-steps per second per core: elements x steps over the CPU time
// (getrusage, all threads) of the steps after the first (the set-up and the stable step
// estimate excluded), divided by the threads.
// Arguments: elements per side, 0 quad4 / 1 tri3, 0 elastic / 1 wrinkling, threads, steps.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>

#include "process_cpu.hpp"
#include "square_membrane.hpp"
#include "velum/analysis/analysis.hpp"
#include "velum/material/linear_sheet_law.hpp"
#include "velum/model/model.hpp"

namespace {

using namespace velum;

using velum::bench::process_cpu;

// The square of clamped_square (E t = 1e6 N/m, ν = 0.3, ρ t = 1 kg/m²), prestressed to
// 1 kN/m both ways, under 100 Pa follower pressure.
std::unique_ptr<Model> prestressed_sheet(int n, bool tri3, bool wrinkling) {
  auto m = std::make_unique<Model>();
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m->add_node(j * (n + 1) + i + 1, Vec3(double(i) / n, double(j) / n, 0.0));
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  std::vector<int> conn, edge;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (tri3)
        conn.insert(conn.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j),
                                 id(i + 1, j + 1), id(i, j + 1)});
      else
        conn.insert(conn.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      if (i == 0 || j == 0 || i == n || j == n) edge.push_back(id(i, j));
  LinearSheetLaw law(PlaneStressLaw::isotropic("film", 1e9, 0.3));
  law.with_prestress(Vec3(1e6, 1e6, 0));
  if (wrinkling) law.with_wrinkling();
  BlockSetupReport report;
  m->blocks.push_back(make_membrane_block(tri3 ? "tri3" : "quad4", "sheet", std::move(conn), m->X,
                                          law, 1000.0, 1e-3, nullptr, shape::Integration::kGauss,
                                          report));
  m->fixed.push_back({edge, {true, true, true}});
  PressureLoad p;
  p.block = 0;
  p.value = 100;
  for (int e = 0; e < m->blocks[0]->size(); ++e) p.elements.push_back(e);
  m->pressures.push_back(std::move(p));
  return m;
}

void BM_ExplicitRun(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const bool tri3 = state.range(1) != 0, wrinkling = state.range(2) != 0;
  const int threads = static_cast<int>(state.range(3)), steps = static_cast<int>(state.range(4));
  omp_set_num_threads(threads);
  auto model = prestressed_sheet(n, tri3, wrinkling);
  const double elements = model->blocks[0]->size();
  double rate = 0, wall_rate = 0, stable = 0, evaluations = 0;
  int done = 0;
  for (auto _ : state) {
    MechanicalSystem sys(*model);
    AnalysisSettings s;
    s.type = AnalysisSettings::Type::kDynamic;
    s.scheme = "central-difference";
    s.time.step = 1e-3;  // capped at the stable step's safety fraction
    s.time.t_end = 1;
    double cpu0 = 0;
    auto t0 = std::chrono::steady_clock::now();
    int taken = 0;
    auto observer = [&](const StepSnapshot& snap) {
      if (snap.step.step == 1) {
        cpu0 = process_cpu();
        t0 = std::chrono::steady_clock::now();
      }
      taken = snap.step.step;
      return taken < steps;
    };
    const AnalysisResult r = run_analysis(sys, s, observer);
    const double cpu = process_cpu() - cpu0;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!r.loop.reason.empty() && taken < steps) state.SkipWithError(r.loop.reason.c_str());
    rate = elements * (taken - 1) / cpu / threads;
    wall_rate = elements * (taken - 1) / wall;
    stable = r.stable_step;
    evaluations = static_cast<double>(r.explicit_step.evaluations);
    done = taken;
  }
  omp_set_num_threads(omp_get_num_procs());
  state.counters["elements"] = elements;
  state.counters["steps"] = done;
  state.counters["stable_step"] = stable;
  // Force evaluations of the stable step's estimates after the start (each about a step's).
  state.counters["estimate_evaluations"] = evaluations;
  state.counters["Melem_steps_per_cpu_s_per_core"] = rate * 1e-6;
  state.counters["Melem_steps_per_wall_s"] = wall_rate * 1e-6;
  state.SetLabel(std::string(tri3 ? "tri3" : "quad4") + (wrinkling ? " wrinkling" : "") + " " +
                 std::to_string(threads) + " thread" + (threads > 1 ? "s" : ""));
}

BENCHMARK(BM_ExplicitRun)
    ->Args({200, 0, 0, 1, 1000})
    ->Args({200, 1, 0, 1, 1000})
    ->Args({200, 0, 1, 1, 1000})
    ->Args({200, 0, 0, 2, 1000})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace
