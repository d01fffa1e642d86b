// How the elements are shared between MPI processes (analysis.partition; docs/parallel.md).
#pragma once

namespace velum {

enum class ElementPartition {
  kRows,    ///< the process owning the matrix row of the element's lowest equation (default)
  kScotch,  ///< PT-Scotch (PETSc's MatPartitioning) on the element graph (shared nodes)
};

}  // namespace velum
