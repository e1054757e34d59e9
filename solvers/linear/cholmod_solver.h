#pragma once
/// Sparse Cholesky factorisation with CHOLMOD's supernodal LLᵀ, split the way a Newton loop with a
/// fixed topology uses it:
///   analyze(pattern)        once per topology: fill-reducing ordering + symbolic factorisation;
///   factorize(values, β)    per Newton step: numeric factorisation of A + βI;
///   solve(b)                any number of times: forward/back substitution with the current factor
///                           (the Newton step, and later the adjoint system with the same matrix).
///
/// The matrix is symmetric and given by its upper triangle in compressed-column form (the layout of
/// BlockAssembly). CHOLMOD's state (cholmod_common, the factor, solve workspaces) lives in a private
/// struct owned by this object; the object is movable, not copyable, and not thread-safe (one
/// solver per thread); analyses with a METIS ordering are run one at a time in the process (METIS
/// draws from one process-wide random generator, cholmod_solver.cpp). CHOLMOD never prints or aborts: its failures come back as
/// cutwork::SolveError with CHOLMOD's reason in words, and an indefinite matrix is a normal
/// `false` from factorize(), leaving the choice of a shift to the caller.
#include <memory>
#include <string>
#include <vector>

namespace cutwork::solvers {

/// Fill-reducing ordering of the symbolic analysis. Automatic chooses by size (see
/// choose_ordering); the others force one of CHOLMOD's methods.
enum class Ordering { Automatic, Amd, Metis, Nesdis };

/// The ordering Automatic picks for an n×n shell Hessian: AMD below kMetisFromDofs unknowns (its
/// analysis is cheap and its fill is within a few percent of METIS' there), METIS from there on
/// (less fill and fewer flops on large meshes; its analysis runs once per topology). Measured on
/// the bench cap, bench/linear_benchmark.cpp BM_Ordering_Cholmod; docs/PERFORMANCE.md.
inline constexpr int kMetisFromDofs = 20000;
Ordering choose_ordering(int n);

class CholmodSolver {
 public:
  explicit CholmodSolver(Ordering ordering = Ordering::Automatic);
  ~CholmodSolver();
  CholmodSolver(CholmodSolver&&) noexcept;
  CholmodSolver& operator=(CholmodSolver&&) noexcept;
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  /// Symbolic analysis for the n×n matrix whose upper triangle has this pattern (column_starts:
  /// n+1, row_indices: nnz, rows sorted within each column). The pattern is copied. Discards any
  /// previous factor. Throws SolveError on failure (e.g. out of memory).
  void analyze(int n, const std::vector<int>& column_starts, const std::vector<int>& row_indices);

  /// Numeric factorisation of A + shift·I, where `values` (nnz, in pattern order) are A's upper
  /// triangle; the values are read, not kept. Returns false when the matrix is not positive
  /// definite (CHOLMOD_NOT_POSDEF; the factor is then invalid). Throws InternalError when called
  /// before analyze(), SolveError when CHOLMOD fails otherwise.
  bool factorize(const double* values, double shift = 0.0);

  /// x = (A + shift·I)⁻¹ b with the current factor (b and x: n entries; may alias).
  /// Throws InternalError when there is no valid factor (check factorize()'s result first).
  void solve(const double* b, double* x) const;

  int size() const;
  bool analyzed() const;
  bool has_factor() const;
  /// Shift of the current factor.
  double shift() const;
  /// CHOLMOD's cheap reciprocal condition estimate (min/max of the factor's diagonal, squared);
  /// 0 without a factor.
  double rcond() const;
  /// Nonzeros of the factor L (after analysis).
  long factor_nonzeros() const;
  /// Floating-point operations of one numeric factorisation (from the analysis; 0 before it). The
  /// thread policy (thread_policy.h) gives OpenBLAS threads by this count.
  double factorization_flops() const;
  /// Name of the fill-reducing ordering CHOLMOD chose (amd, metis, nesdis, …).
  std::string ordering() const;
  /// True when the factor is supernodal (it always is after analyze()).
  bool supernodal() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace cutwork::solvers
