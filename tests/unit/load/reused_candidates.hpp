// The sheet contact's candidates (docs/contact.md "Sheets", "Search") reused while no node has
// moved past half the skin: the term's forces and matrix at moved states against a fresh
// search's (a term with no candidates yet, restored to the same accepted state), to the last
// bit. Shared by the sheet and edge contact tests.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "load/sheet_contact_term.hpp"
#include "velum/analysis/mechanical_system.hpp"

namespace velum::test {

// Forces (every node, held ones too) and matrix of the sheet contact `term` of `sys` at x.
inline void sheet_term_at(MechanicalSystem& sys, LoadTerm& term, const NodePositions& x,
                          NodePositions& F, MatX& K) {
  SparseMatrix Ks;
  sys.assembler().make_matrix(Ks);
  LowRankJacobian L;
  F = NodePositions::Zero(3, x.cols());
  const NodePositions V = NodePositions::Zero(3, x.cols());
  LoadOutput out{.F = F, .K = &Ks, .low_rank = &L, .column = 0};
  term.add(LoadState{.t = 0, .x = x, .V = V}, out);
  K = MatX(Ks);
}

// The model's last load a sheet contact, started at its reference: every node moved at random
// in every direction by at most `small` (below half the skin: the start's candidates reused),
// then by up to `large` (past it: a new candidate search), then by at most `small` again
// (reused). At each state the forces and matrix equal a fresh search's exactly.
inline void check_reused_candidates(Model& m, double small, double large, const char* what) {
  MechanicalSystem a(m);
  const VecX zero = VecX::Zero(a.size());
  a.start_loads(0, zero, zero);
  auto& ta = dynamic_cast<sheet_contact::SheetContactTerm&>(*a.loads().back());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  NodePositions x = m.X;
  struct Move {
    double size;
    int searches;  ///< new candidate searches it brings
  };
  int touching = 0;
  for (const Move move : {Move{small, 0}, Move{large, 1}, Move{small, 0}}) {
    for (int n = 0; n < m.num_nodes(); ++n) {
      Vec3 d(u(rng), u(rng), u(rng));
      while (d.norm() > 1 || d.norm() == 0) d = Vec3(u(rng), u(rng), u(rng));
      x.col(n) += move.size * d;
    }
    const int before = ta.candidate_searches();
    NodePositions Fa, Fb;
    MatX Ka, Kb;
    sheet_term_at(a, ta, x, Fa, Ka);
    EXPECT_EQ(ta.candidate_searches(), before + move.searches) << what << ", move " << move.size;
    MechanicalSystem b(m);
    b.restore_load_state(a.save_load_state());
    auto& tb = dynamic_cast<sheet_contact::SheetContactTerm&>(*b.loads().back());
    sheet_term_at(b, tb, x, Fb, Kb);
    EXPECT_EQ(tb.candidate_searches(), 1) << what;
    EXPECT_EQ((Fa - Fb).cwiseAbs().maxCoeff(), 0.0) << what << ", move " << move.size;
    EXPECT_EQ((Ka - Kb).cwiseAbs().maxCoeff(), 0.0) << what << ", move " << move.size;
    touching += Fa.cwiseAbs().maxCoeff() > 0 ? 1 : 0;
    std::cout << what << ", nodes moved up to " << move.size << ": forces " << Fa.norm()
              << ", matrix " << Ka.norm() << ", candidate searches " << ta.candidate_searches()
              << "\n";
  }
  EXPECT_EQ(touching, 3) << what;  // in contact at every state
}

}  // namespace velum::test
