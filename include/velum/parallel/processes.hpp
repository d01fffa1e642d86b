// The MPI processes of a run (docs/parallel.md). Every process runs the same Newton loop, step
// control and integrator on its piece of the model (its own elements and their nodes, its
// equations and their ghosts); the processes meet in the distributed linear solve (PETSc), in
// the sums and exchanges below, and in the few decisions that must agree (stop after this
// step). Without PETSc in the build, or when not launched by mpirun, there is one process and
// every call here is trivial.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace velum::processes {

/// Whether this build has PETSc and MPI (VELUM_WITH_PETSC).
bool have_petsc();
/// The size mpirun (OpenMPI, MPICH/Hydra, PMIx) announced in the environment; 1 otherwise.
int launched_size();
/// Initialises MPI and PETSc when launched by mpirun (several processes), before anything is
/// read: every process must reach every collective call. Returns false (with a message on
/// stderr) when several processes were launched but this build has no PETSc.
bool start(int* argc, char*** argv);
/// In the one-process executable (`velum`, built without PETSc: it starts about 0.06 s of CPU
/// faster), runs `velum-mpi` from the same directory, the same program with PETSc, with main's
/// arguments in place of this process (exec: it does not return then). Called when several
/// processes were launched or a model asks for `linear_solver: petsc`, before anything is
/// written. Returns false when this build has PETSc, or no velum-mpi is there.
bool relaunch_with_petsc();
/// True in a one-process run relaunched so (its first lines were printed already).
bool relaunched();
/// Initialises MPI and PETSc on first use in a one-process run (a model with
/// `linear_solver: petsc`): MPI's singleton start costs about a second, paid only then.
void ensure_started();
/// PetscFinalize (and MPI_Finalize) when started; call once, at the end of main.
void finish();

int rank();   ///< this process, 0 .. count() − 1
int count();  ///< processes in the run
/// True on every process when `local` is true on every process (a collective call).
bool all(bool local);
/// Sums data[0 .. n) over the processes, in place, the same bits on every process (reduced
/// to the first process, then broadcast: an all-reduce may add in a different order on
/// different processes, and the processes' decisions must agree). A collective call; nothing
/// on one process.
void sum(double* data, long n);
/// Each process's `value`, in rank order, on the first process (empty on the others). A
/// collective call; {value} on one process.
std::vector<double> gather(double value);
/// Each process's `values` (of any length), in rank order, concatenated, on the first process
/// (empty on the others). A collective call; `values` on one process.
std::vector<double> gather(const std::vector<double>& values);
/// The smallest of every process's `value`, on every process. A collective call.
long min(long value);
/// The largest of every process's `value`, on every process. A collective call.
double max(double value);
/// Point to point: send[p] goes to process p; returns received[p], what process p sent
/// here (its send[rank()]). A collective call; on one process, send itself.
std::vector<std::vector<double>> exchange(const std::vector<std::vector<double>>& send);
std::vector<std::vector<long>> exchange(const std::vector<std::vector<long>>& send);
/// One message of a neighbour exchange: `count` doubles at `at` in the buffer, to or from
/// process `rank`.
struct Channel {
  int rank = 0;
  int at = 0;
  int count = 0;
};
/// Point to point with the listed processes only (MPI_Isend / MPI_Irecv per channel, then
/// MPI_Waitall): out[c.at .. + c.count) goes to c.rank for each c of `to`, and what f.rank
/// sends lands at in[f.at ..) for each f of `from`. Each process listed must list this one
/// the other way with the same count. No process outside the lists is involved; a process
/// with no channel returns at once. Nothing on one process.
void exchange(const double* out, const std::vector<Channel>& to, double* in,
              const std::vector<Channel>& from);
/// The process that owns item k of `total` split into count() contiguous, even ranges (as
/// PETSc splits rows).
int owner(long k, long total);
/// The same for `count` processes (the split of a model into parts on one process).
inline int owner(long k, long total, int count) {
  const long base = total / count, extra = total % count;
  const long split = extra * (base + 1);  // the first `extra` processes hold base + 1 items
  return static_cast<int>(k < split ? k / (base + 1) : extra + (k - split) / std::max(base, 1L));
}
/// Where part r of `total` items split into `parts` contiguous ranges of whole blocks of
/// `block` items (total a multiple of it), as even as PETSc's own split, starts; r = parts
/// gives `total`.
inline long range_start(long total, int block, int parts, int r) {
  const long blocks = total / block, base = blocks / parts, extra = blocks % parts;
  return block * (r * base + (r < extra ? r : extra));
}
/// A partition of a graph (vertices 0 .. n − 1, the neighbours of v at
/// adjacency[offsets[v] .. offsets[v + 1]), ascending, without v) into count() parts by
/// PT-Scotch through PETSc's MatPartitioning: part[v] on every process, the same. A collective
/// call; every process passes the same graph. False, with `why`, on every process when the
/// partitioner is not available (or failed).
bool partition_graph(const std::vector<long>& offsets, const std::vector<long>& adjacency,
                     std::vector<int>& part, std::string& why);

}  // namespace velum::processes
