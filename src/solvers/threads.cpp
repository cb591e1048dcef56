// The libraries' threads (threads.hpp), found at run time: the BLAS is whatever
// libblas.so.3 resolves to (Debian's alternatives: reference BLAS, OpenBLAS, BLIS), the OpenMP
// runtime the one CHOLMOD links (libgomp).
#include "cbps/solvers/threads.hpp"

#include <dlfcn.h>

#include <climits>
#include <cstdlib>
#include <filesystem>

namespace cbps {

namespace {

/// A function of the process's loaded libraries by name, or nullptr.
template <typename F>
F* find(const char* name) {
  return reinterpret_cast<F*>(::dlsym(RTLD_DEFAULT, name));
}

int requested_threads = -1;  ///< -1: set_threads not called

/// The resolved file of the library that holds the BLAS's dgemm_, or "".
std::string blas_file() {
  void* dgemm = ::dlsym(RTLD_DEFAULT, "dgemm_");
  Dl_info info{};
  if (dgemm == nullptr || ::dladdr(dgemm, &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code ec;
  const std::filesystem::path resolved = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::string(info.dli_fname) : resolved.string();
}

}  // namespace

ThreadReport thread_report() {
  ThreadReport r;
  r.requested = requested_threads < 0 ? 0 : requested_threads;
  r.blas = blas_file();
  if (auto* get = find<int()>("openblas_get_num_threads")) {
    r.blas_kind = "openblas";
    r.blas_threads = get();
  } else if (auto* get_blis = find<long()>("bli_thread_get_num_threads")) {
    r.blas_kind = "blis";
    r.blas_threads = static_cast<int>(get_blis());
  } else {
    r.blas_kind = "single-threaded";
    r.blas_threads = 1;
  }
  if (auto* omp_max = find<int()>("omp_get_max_threads")) r.openmp_threads = omp_max();
  if (auto* levels = find<int()>("omp_get_max_active_levels"); levels != nullptr && levels() == 0)
    r.openmp_threads = 1;  // every region inactive: one thread, whatever a region asks
  return r;
}

ThreadReport set_threads(int threads) {
  requested_threads = threads < 0 ? 0 : threads;
  if (threads > 0) {
    if (auto* set = find<void(int)>("openblas_set_num_threads")) set(threads);
    if (auto* set_blis = find<void(long)>("bli_thread_set_num_threads")) set_blis(threads);
    if (auto* set_omp = find<void(int)>("omp_set_num_threads")) set_omp(threads);
    // CHOLMOD's parallel loops name their team's size themselves (num_threads(4): SuiteSparse
    // 5.12's CHOLMOD_OMP_NUM_THREADS), past omp_set_num_threads: one thread asked, OpenMP's
    // regions are made inactive (at most 0 active levels), so that they run on the calling
    // thread. A team of 4 spinning on 2 cores made the relaxation's interior point on the
    // 1,600-contact pyramid 1.75x slower (0.35 s against 0.20 s, docs/cli-contract.md).
    if (auto* levels = find<void(int)>("omp_set_max_active_levels"); levels && threads == 1)
      levels(0);
  }
  return thread_report();
}

}  // namespace cbps
