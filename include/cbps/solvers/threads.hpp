// How many threads the libraries under the exact path use: CHOLMOD calls the BLAS (dense
// supernodal updates) and OpenMP. cbps is single-threaded itself, so their threads are all it
// has; Debian's BLAS may be OpenBLAS's pthread build, which starts one worker per core when it
// loads and was measured 1.4-1.8x slower than one thread on a loaded 2-core machine (4,800-row
// pyramid, row-space factorization). cbps therefore chooses: one thread unless asked
// (`--threads N`), applied to whichever BLAS and OpenMP runtime the process loaded, and
// reported (summary.json "threads").
#pragma once

#include <string>

namespace cbps {

/// What the process runs with after set_threads.
struct ThreadReport {
  int requested = 1;       ///< the request: N, or 0 for the libraries' own choice
  std::string blas;        ///< the BLAS library loaded (its resolved file), "" if none found
  std::string blas_kind;   ///< "openblas", "blis" or "single-threaded" (no thread control)
  int blas_threads = 1;    ///< threads the BLAS uses now
  int openmp_threads = 0;  ///< OpenMP's max threads now, 0 when no OpenMP runtime is loaded
};

/// Sets the BLAS's and OpenMP's threads to `threads` (≥ 1), or with 0 leaves each library's
/// own default (OPENBLAS_NUM_THREADS, OMP_NUM_THREADS, else the core count). With 1, OpenMP's
/// parallel regions are made inactive too: CHOLMOD's name their own team of 4. Found at run time
/// (dlsym), so any BLAS works; one without thread control is reported single-threaded.
ThreadReport set_threads(int threads);

/// The report of the last set_threads (or of the libraries' defaults if it was not called).
ThreadReport thread_report();

}  // namespace cbps
