#include "velum/parallel/processes.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <type_traits>
#include <vector>

#ifdef VELUM_HAVE_PETSC
#include <petscmat.h>
#else
#include <unistd.h>
#endif

namespace velum::processes {
namespace {

[[maybe_unused]] bool started = false;  // MPI and PETSc initialised (a PETSc build)
int my_rank = 0, my_count = 1;
char** saved_argv = nullptr;  ///< main's arguments, for relaunch_with_petsc

int env_int(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : 0;
}

#ifdef VELUM_HAVE_PETSC
void initialize(int* argc, char*** argv) {
  if (started) return;
  // PETSc reads no command line of ours (velum's options are not PETSc's): options come from
  // analysis.petsc_options only.
  int no_argc = 0;
  char** no_argv = nullptr;
  (void)argc, (void)argv;
  if (PetscInitialize(&no_argc, &no_argv, nullptr, nullptr) != 0) {
    std::fputs("error: PETSc failed to initialise\n", stderr);
    std::exit(4);
  }
  // Errors come back as codes (the solver reports them and a step is cut), never as PETSc's
  // own message and abort.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  MPI_Comm_rank(PETSC_COMM_WORLD, &my_rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &my_count);
  started = true;
}
#endif

}  // namespace

bool have_petsc() {
#ifdef VELUM_HAVE_PETSC
  return true;
#else
  return false;
#endif
}

int launched_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "MPI_LOCALNRANKS"})
    if (const int n = env_int(name); n > 0) return n;
  return 1;
}

bool relaunched() {
  return launched_size() <= 1 && std::getenv("VELUM_RELAUNCHED") != nullptr;
}

bool relaunch_with_petsc() {
#ifdef VELUM_HAVE_PETSC
  return false;
#else
  // The one-process executable leaves out PETSc, whose hundred shared libraries cost about
  // 0.06 s of CPU at every start; its sibling velum-mpi is the same program with them.
  if (saved_argv == nullptr || saved_argv[0] == nullptr) return false;
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return false;
  self[n] = '\0';
  std::string sibling(self);
  const size_t slash = sibling.rfind('/');
  sibling = sibling.substr(0, slash + 1) + "velum-mpi";
  if (sibling == self || access(sibling.c_str(), X_OK) != 0) return false;
  std::fflush(nullptr);
  setenv("VELUM_RELAUNCHED", "1", 1);  // what this process printed is not printed again
  execv(sibling.c_str(), saved_argv);
  return false;  // exec failed: the caller says what is missing
#endif
}

bool start(int* argc, char*** argv) {
  if (argv) saved_argv = *argv;
  const int n = launched_size();
  if (n <= 1) return true;
#ifdef VELUM_HAVE_PETSC
  initialize(argc, argv);
  return true;
#else
  (void)argc;
  relaunch_with_petsc();  // returns only when there is no velum-mpi beside this executable
  if (env_int("OMPI_COMM_WORLD_RANK") == 0 && env_int("PMI_RANK") == 0)
    std::fprintf(stderr,
                 "error: launched on %d processes, but this build of velum has no PETSc and MPI "
                 "(install petsc-dev and rebuild with VELUM_WITH_PETSC=ON), or run on one "
                 "process\n",
                 n);
  return false;
#endif
}

void ensure_started() {
#ifdef VELUM_HAVE_PETSC
  if (started) return;
  initialize(nullptr, nullptr);
  std::atexit(finish);  // a program that never calls finish() (tests) still ends MPI cleanly
#endif
}

void finish() {
#ifdef VELUM_HAVE_PETSC
  if (started) PetscFinalize();
  started = false;
#endif
}

int rank() {
  return my_rank;
}
int count() {
  return my_count;
}

bool all(bool local) {
#ifdef VELUM_HAVE_PETSC
  if (my_count > 1) {
    int in = local ? 1 : 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
    return out != 0;
  }
#endif
  return local;
}

void sum(double* data, long n) {
#ifdef VELUM_HAVE_PETSC
  if (my_count > 1 && n > 0) {
    // In pieces: MPI counts are int.
    constexpr long kPiece = 1L << 26;
    std::vector<double> total(static_cast<size_t>(std::min(n, kPiece)));
    for (long first = 0; first < n; first += kPiece) {
      const int m = static_cast<int>(std::min(kPiece, n - first));
      MPI_Reduce(data + first, total.data(), m, MPI_DOUBLE, MPI_SUM, 0, PETSC_COMM_WORLD);
      if (my_rank == 0) std::copy(total.begin(), total.begin() + m, data + first);
      MPI_Bcast(data + first, m, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
    }
  }
#else
  (void)data, (void)n;
#endif
}

std::vector<double> gather(double value) {
#ifdef VELUM_HAVE_PETSC
  if (my_count > 1) {
    std::vector<double> all(my_rank == 0 ? my_count : 0);
    MPI_Gather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
    return all;
  }
#endif
  return {value};
}

std::vector<double> gather(const std::vector<double>& values) {
#ifdef VELUM_HAVE_PETSC
  if (my_count > 1) {
    const int n = static_cast<int>(values.size());
    std::vector<int> counts(my_rank == 0 ? static_cast<size_t>(my_count) : 0), at;
    MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, PETSC_COMM_WORLD);
    int total = 0;
    for (int c : counts) at.push_back(total), total += c;
    std::vector<double> all(static_cast<size_t>(total));
    MPI_Gatherv(values.data(), n, MPI_DOUBLE, all.data(), counts.data(), at.data(), MPI_DOUBLE, 0,
                PETSC_COMM_WORLD);
    return all;
  }
#endif
  return values;
}

namespace {

// The smallest (largest) of every process's `value`, on every process.
template <class T>
T all_reduce(T value, [[maybe_unused]] bool largest) {
#ifdef VELUM_HAVE_PETSC
  if (my_count > 1) {
    T out = value;
    const bool real = std::is_same_v<T, double>;  // outside the call: PETSc wraps it in a macro
    MPI_Allreduce(&value, &out, 1, real ? MPI_DOUBLE : MPI_LONG, largest ? MPI_MAX : MPI_MIN,
                  PETSC_COMM_WORLD);
    return out;
  }
#endif
  return value;
}

}  // namespace

long min(long value) {
  return all_reduce(value, false);
}

double max(double value) {
  return all_reduce(value, true);
}

namespace {

template <class T>
std::vector<std::vector<T>> exchange_of(const std::vector<std::vector<T>>& send) {
#ifdef VELUM_HAVE_PETSC
  if (my_count > 1) {
    const MPI_Datatype type = std::is_same_v<T, double> ? MPI_DOUBLE : MPI_LONG;
    const auto p = static_cast<size_t>(my_count);
    std::vector<int> send_count(p), recv_count(p), send_at(p + 1, 0), recv_at(p + 1, 0);
    for (size_t q = 0; q < p; ++q) send_count[q] = static_cast<int>(send[q].size());
    MPI_Alltoall(send_count.data(), 1, MPI_INT, recv_count.data(), 1, MPI_INT, PETSC_COMM_WORLD);
    for (size_t q = 0; q < p; ++q) {
      send_at[q + 1] = send_at[q] + send_count[q];
      recv_at[q + 1] = recv_at[q] + recv_count[q];
    }
    std::vector<T> out(static_cast<size_t>(send_at[p])), in(static_cast<size_t>(recv_at[p]));
    for (size_t q = 0; q < p; ++q)
      std::copy(send[q].begin(), send[q].end(), out.begin() + send_at[q]);
    MPI_Alltoallv(out.data(), send_count.data(), send_at.data(), type, in.data(), recv_count.data(),
                  recv_at.data(), type, PETSC_COMM_WORLD);
    std::vector<std::vector<T>> received(p);
    for (size_t q = 0; q < p; ++q)
      received[q].assign(in.begin() + recv_at[q], in.begin() + recv_at[q + 1]);
    return received;
  }
#endif
  return send;
}

}  // namespace

std::vector<std::vector<double>> exchange(const std::vector<std::vector<double>>& send) {
  return exchange_of(send);
}

std::vector<std::vector<long>> exchange(const std::vector<std::vector<long>>& send) {
  return exchange_of(send);
}

void exchange(const double* out, const std::vector<Channel>& to, double* in,
              const std::vector<Channel>& from) {
#ifdef VELUM_HAVE_PETSC
  if (my_count <= 1 || (to.empty() && from.empty())) return;
  constexpr int kTag = 4601;  // one message each way per pair and call; calls do not overlap
  thread_local std::vector<MPI_Request> requests;
  requests.assign(from.size() + to.size(), MPI_REQUEST_NULL);
  size_t r = 0;
  // Receives posted first, so that a send finds its receive waiting.
  for (const Channel& f : from)
    MPI_Irecv(in + f.at, f.count, MPI_DOUBLE, f.rank, kTag, PETSC_COMM_WORLD, &requests[r++]);
  for (const Channel& t : to)
    MPI_Isend(out + t.at, t.count, MPI_DOUBLE, t.rank, kTag, PETSC_COMM_WORLD, &requests[r++]);
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
#else
  (void)out, (void)to, (void)in, (void)from;
#endif
}

int owner(long k, long total) {
  return owner(k, total, my_count);
}

bool partition_graph(const std::vector<long>& offsets, const std::vector<long>& adjacency,
                     std::vector<int>& part, std::string& why) {
  const long n = static_cast<long>(offsets.size()) - 1;
  part.assign(static_cast<size_t>(std::max(n, 0L)), 0);
#ifdef VELUM_HAVE_PETSC
  if (my_count <= 1) return true;
  // This process hands PETSc its contiguous share of the vertices (their rows of the graph).
  const long base = n / my_count, extra = n % my_count;
  const long begin = my_rank * base + std::min<long>(my_rank, extra);
  const long end = begin + base + (my_rank < extra ? 1 : 0);
  PetscInt *ia = nullptr, *ja = nullptr;  // MatCreateMPIAdj takes them (PETSc frees them)
  const long edges = offsets[end] - offsets[begin];
  bool ok = PetscMalloc1(end - begin + 1, &ia) == 0 && PetscMalloc1(std::max(edges, 1L), &ja) == 0;
  Mat graph = nullptr;
  MatPartitioning mp = nullptr;
  IS mine = nullptr, gathered = nullptr;
  if (ok) {
    for (long v = begin; v <= end; ++v)
      ia[v - begin] = static_cast<PetscInt>(offsets[v] - offsets[begin]);
    for (long k = 0; k < edges; ++k) ja[k] = static_cast<PetscInt>(adjacency[offsets[begin] + k]);
    ok = MatCreateMPIAdj(PETSC_COMM_WORLD, static_cast<PetscInt>(end - begin),
                         static_cast<PetscInt>(n), ia, ja, nullptr, &graph) == 0;
    if (!ok) PetscFree(ia), PetscFree(ja);
  }
  ok = ok && MatPartitioningCreate(PETSC_COMM_WORLD, &mp) == 0 &&
       MatPartitioningSetAdjacency(mp, graph) == 0 && MatPartitioningSetNParts(mp, my_count) == 0;
  if (ok && MatPartitioningSetType(mp, MATPARTITIONINGPTSCOTCH) != 0) {
    ok = false;
    why = "this PETSc has no PT-Scotch (MatPartitioning type ptscotch)";
  }
  ok = processes::all(ok);  // every process goes on, or none
  if (ok) {
    ok = MatPartitioningApply(mp, &mine) == 0 && ISAllGather(mine, &gathered) == 0;
    const PetscInt* idx = nullptr;
    PetscInt size = 0;
    if (ok && ISGetLocalSize(gathered, &size) == 0 && size == n &&
        ISGetIndices(gathered, &idx) == 0) {
      for (long v = 0; v < n; ++v) part[static_cast<size_t>(v)] = static_cast<int>(idx[v]);
      ISRestoreIndices(gathered, &idx);
    } else {
      ok = false;
    }
    ok = processes::all(ok);
    if (!ok) why = "PT-Scotch failed to partition the element graph";
  } else if (why.empty()) {
    why = "PETSc could not set up the graph partition";
  }
  ISDestroy(&gathered);
  ISDestroy(&mine);
  MatPartitioningDestroy(&mp);
  MatDestroy(&graph);
  if (!ok) part.assign(part.size(), 0);
  return ok;
#else
  (void)adjacency;
  why = "this build has no PETSc";
  return my_count <= 1;
#endif
}

}  // namespace velum::processes
