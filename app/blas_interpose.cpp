// dgemm_ and dtrsm_ for the whole process: one-column calls become dgemv/dtrsv
// (core/solve/blas_single_rhs.h says why), all others go on to the BLAS the process loaded.
// Linked into the flexframe executable itself and exported (interpose.list), so the shared
// solver libraries bind to these before the BLAS library.
#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>

#include "core/solve/blas_single_rhs.h"

namespace {
template <class F>
F next_symbol(const char* name) {
  void* f = dlsym(RTLD_NEXT, name);
  if (!f) {  // no BLAS behind us: nothing sensible can continue
    std::fprintf(stderr, "flexframe: the BLAS routine %s is not loaded (%s)\n", name, dlerror());
    std::abort();
  }
  return reinterpret_cast<F>(f);
}
using Gemm = void (*)(const char*, const char*, const int*, const int*, const int*, const double*, const double*,
                      const int*, const double*, const int*, const double*, double*, const int*);
using Trsm = void (*)(const char*, const char*, const char*, const char*, const int*, const int*, const double*,
                      const double*, const int*, double*, const int*);
}  // namespace

extern "C" void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
                       const double* alpha, const double* A, const int* lda, const double* B, const int* ldb,
                       const double* beta, double* C, const int* ldc) {
  if (ff::blas::gemm_one_column(*transa, *transb, *m, *n, *k, *alpha, A, *lda, B, *ldb, *beta, C, *ldc)) return;
  static const Gemm next = next_symbol<Gemm>("dgemm_");
  next(transa, transb, m, n, k, alpha, A, lda, B, ldb, beta, C, ldc);
}

extern "C" void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
                       const int* n, const double* alpha, const double* A, const int* lda, double* B,
                       const int* ldb) {
  if (ff::blas::trsm_one_column(*side, *uplo, *transa, *diag, *m, *n, *alpha, A, *lda, B, *ldb)) return;
  static const Trsm next = next_symbol<Trsm>("dtrsm_");
  next(side, uplo, transa, diag, m, n, alpha, A, lda, B, ldb);
}
