#include "ordering.hpp"

#include <cholmod.h>

#include <algorithm>

namespace velum {

bool same_rows(const SparseMatrix& A, int a, int b) {
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  return outer[a + 1] - outer[a] == outer[b + 1] - outer[b] &&
         std::equal(inner + outer[a], inner + outer[a + 1], inner + outer[b]);
}

std::vector<int> nested_dissection(const SparseMatrix& A) {
  const int n = static_cast<int>(A.cols());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  // Supervariables: runs of consecutive columns with the same rows (a node's equations are
  // numbered together).
  std::vector<int> first{0}, group(n);
  for (int j = 0; j < n; ++j) {
    if (j > first.back() && !same_rows(A, first.back(), j)) first.push_back(j);
    group[j] = static_cast<int>(first.size()) - 1;
  }
  const int m = static_cast<int>(first.size());
  first.push_back(n);
  // The graph of the supervariables, one column each (rows sorted, each once).
  std::vector<int> p(m + 1, 0), rows;
  rows.reserve(A.nonZeros() / std::max(1, n / m) + m);
  for (int g = 0; g < m; ++g) {
    const int j = first[g];
    int last = -1;
    for (int k = outer[j]; k < outer[j + 1]; ++k)
      if (const int h = group[inner[k]]; h != last) rows.push_back(last = h);
    p[g + 1] = static_cast<int>(rows.size());
  }
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  cholmod_sparse G{};
  G.nrow = G.ncol = static_cast<size_t>(m);
  G.nzmax = rows.size();
  G.p = p.data();
  G.i = rows.data();
  G.stype = 1;  // symmetric, upper triangle read
  G.itype = CHOLMOD_INT;
  G.xtype = CHOLMOD_PATTERN;
  G.dtype = CHOLMOD_DOUBLE;
  G.sorted = G.packed = 1;
  std::vector<int> order(m);
  std::vector<int> parent(m), member(m);  // the separator tree: not needed
  const bool ok = cholmod_nested_dissection(&G, nullptr, 0, order.data(), parent.data(),
                                            member.data(), &c) >= 0 &&
                  c.status == CHOLMOD_OK;
  cholmod_finish(&c);
  if (!ok) return {};
  std::vector<int> position(n);
  int next = 0;
  for (const int g : order)
    for (int j = first[g]; j < first[g + 1]; ++j) position[j] = next++;
  return position;
}

}  // namespace velum
