// What sheet contact adds to a Newton iteration (issue 41: at most 20 % of it, linear in the
// faces): two n x n quad4 sheets, the upper one resting on the lower one (every upper node in
// contact), one Newton iteration = assembling the residual and tangent, factorising, one
// solve, with the contact term and without it (the same sheets apart). Counters, seconds per
// iteration (CPU, all threads; medians of up to 9 iterations each): `with_s`, `without_s`,
// and of the iteration with contact
// `contact_share`; the contact term alone (`term_s`: search, the couplings' check, pairs and
// their matrix blocks) and its share of the iteration with contact (`term_share`); the
// assembly (`assembly_with_s`, `assembly_without_s`: residual and tangent) and the
// factorisation with its solve (`factor_with_s`, `factor_without_s`), and the Jacobian's
// entries with the contact's node couplings over those without (`entries_ratio`). Faces: the
// lower sheet's 2 n² triangles. Second argument: 0 the lower sheet held (as measured before
// 2026-12-05's couplings), 1 free inside its edges.
#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <algorithm>
#include <memory>
#include <tuple>
#include <vector>

#include "velum/analysis/mechanical_system.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/model/model.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/low_rank_solver.hpp"

namespace {

using namespace velum;
// User + system CPU seconds of the process, all threads (the honest figure on a shared
// machine).
double cpu() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

// Two sheets 1 m square, 1 mm thick, prestressed (so each has a stiffness across its plane
// without the other): the upper one a contact thickness above the lower one
// less 1 µm, so every upper node presses; edges held, the upper sheet's inner nodes free, and
// with `lower_free` the lower sheet's too (the node–face couplings then join free equations:
// the Jacobian's pattern grows and the two sheets are factorised together).
std::unique_ptr<Model> two_sheets(int n, bool contact, bool lower_free) {
  auto m = std::make_unique<Model>();
  const double t = 1e-3;
  std::vector<int> edge;
  for (int layer = 0; layer < 2; ++layer) {
    const int first = m->num_nodes();
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        m->add_node(first + j * (n + 1) + i + 1,
                    Vec3(double(i) / n, double(j) / n, layer * (t - 1e-6)));
        if ((layer == 0 && !lower_free) || i == 0 || j == 0 || i == n || j == n)
          edge.push_back(first + j * (n + 1) + i);
      }
    std::vector<int> conn;
    auto id = [&](int i, int j) { return first + j * (n + 1) + i; };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        conn.insert(conn.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    BlockSetupReport report;
    m->blocks.push_back(make_membrane_block(
        "quad4", layer ? "top" : "bottom", std::move(conn), m->X,
        SheetLaw(PlaneStressLaw::isotropic("film", 1e9, 0.3)).with_prestress({1e6, 1e6, 0}), 1000.0,
        t, nullptr, shape::Integration::kGauss, report));
  }
  m->fixed.push_back({edge, {true, true, true}});
  if (contact) {
    ContactLoad cl;
    cl.parts.push_back({1, {}});
    cl.other.push_back({0, {}});
    for (int e = 0; e < m->blocks[0]->size(); ++e)
      cl.parts[0].elements.push_back(e), cl.other[0].elements.push_back(e);
    m->loads.add(make_load(cl));
  }
  for (auto& l : m->loads) l->set_up(*m);
  return m;
}

struct Iteration {
  double total = 0, assembly = 0, factor = 0, entries = 0;
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Newton iterations on one system, the symbolic analysis done before: each iteration's
// parts appended to the lists.
struct Newton {
  explicit Newton(MechanicalSystem& s)
      : sys(s),
        sparse(make_linear_solver(SolverKind::kAuto)),
        solver(*sparse, sys),
        zero(VecX::Zero(sys.size())) {
    sys.evaluate(0, zero, zero, zero, 1, 0, 0, r, &J);
    solver.refactorize(J, sys.pattern_revision());
  }
  void iterate() {
    const double t0 = cpu();
    sys.evaluate(0, zero, zero, zero, 1, 0, 0, r, &J);
    const double t1 = cpu();
    solver.refactorize(J, sys.pattern_revision());
    solver.solve(-r, du);
    const double t2 = cpu();
    total.push_back(t2 - t0), assembly.push_back(t1 - t0), factor.push_back(t2 - t1);
  }
  Iteration medians() const {
    return {median(total), median(assembly), median(factor), static_cast<double>(J.nonZeros())};
  }
  MechanicalSystem& sys;
  std::unique_ptr<LinearSolver> sparse;
  LowRankCorrectedSolver solver;
  VecX zero, r, du;
  SparseMatrix J;
  std::vector<double> total, assembly, factor;
};

// The medians of `reps` iterations with and without contact, taken in turn (one iteration's
// CPU time varies by a fifth on a shared machine, and the share is a difference of two such
// times: alternating, a slow minute slows both).
std::pair<Iteration, Iteration> iterate(MechanicalSystem& with, MechanicalSystem& without,
                                        int reps) {
  Newton a(with), b(without);
  for (int k = 0; k < reps; ++k) a.iterate(), b.iterate();
  return {a.medians(), b.medians()};
}

void BM_ContactShareOfNewtonIteration(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const bool lower_free = state.range(1) != 0;
  const auto with = two_sheets(n, true, lower_free), without = two_sheets(n, false, lower_free);
  MechanicalSystem sys_with(*with), sys_without(*without);
  Iteration a, b;
  double term = 0;
  // The contact term alone: its couplings' check (the search) and its forces and matrix
  // blocks at the pressed state, as the system calls them, into outputs allocated (and their
  // pages touched) before the timer, as the system's are between iterations; the matrix on
  // the pattern with the couplings (made once the system has evaluated a Jacobian).
  NodePositions F = NodePositions::Zero(3, with->num_nodes());
  SparseMatrix K;
  LowRankJacobian L;
  const NodePositions V = NodePositions::Zero(3, with->num_nodes());
  // Medians of 9 at 10k faces, fewer on larger sheets (at least 2).
  const int reps = std::max(2, static_cast<int>(90000 / (2.0 * n * n)));
  for (auto _ : state) {
    std::tie(a, b) = iterate(sys_with, sys_without, reps);
    sys_with.assembler().make_matrix(K);
    LoadTerm& contact = *sys_with.loads().back();
    std::vector<double> search, whole;
    for (int k = 0; k < reps; ++k) {
      F.setZero();
      LoadOutput out{.F = F, .K = &K, .low_rank = &L, .column = 0};
      const double t0 = cpu();
      const bool changed = contact.update_couplings(with->X);
      search.push_back(cpu() - t0);
      contact.add(LoadState{.t = 0, .x = with->X, .V = V}, out);
      whole.push_back(cpu() - t0);
      if (changed) state.SkipWithError("the couplings changed at the state already evaluated");
    }
    state.counters["search_s"] = median(search);
    term = median(whole);
  }
  state.counters["faces"] = 2.0 * n * n;
  state.counters["with_s"] = a.total;
  state.counters["without_s"] = b.total;
  state.counters["term_s"] = term;
  state.counters["contact_share"] = (a.total - b.total) / a.total;
  state.counters["term_share"] = term / a.total;
  state.counters["assembly_with_s"] = a.assembly;
  state.counters["assembly_without_s"] = b.assembly;
  state.counters["factor_with_s"] = a.factor;
  state.counters["factor_without_s"] = b.factor;
  state.counters["entries_ratio"] = a.entries / b.entries;
  state.SetComplexityN(2L * n * n);
}

BENCHMARK(BM_ContactShareOfNewtonIteration)
    ->Args({71, 0})   // 10k faces, the lower sheet held
    ->Args({224, 0})  // 100k
    ->Args({707, 0})  // 1M (left out of make bench: tools/run-bench, heavy)
    ->Args({71, 1})   // 10k, both sheets free inside their edges
    ->Args({224, 1})  // 100k
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
