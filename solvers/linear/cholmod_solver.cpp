#include "solvers/linear/cholmod_solver.h"

#include <cholmod.h>

#include <algorithm>
#include <cstring>
#include <mutex>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "solvers/linear/large_pages.h"
#include "solvers/linear/thread_policy.h"

namespace cutwork::solvers {

namespace {

std::string status_text(int status) {
  switch (status) {
    case CHOLMOD_OK: return "ok";
    case CHOLMOD_NOT_INSTALLED: return "a CHOLMOD module is not installed";
    case CHOLMOD_OUT_OF_MEMORY: return "out of memory (try a coarser simulation mesh)";
    case CHOLMOD_TOO_LARGE: return "the problem is too large for CHOLMOD's integer type";
    case CHOLMOD_INVALID: return "invalid input to CHOLMOD (an internal error in cutwork)";
    case CHOLMOD_GPU_PROBLEM: return "CHOLMOD GPU failure";
    case CHOLMOD_NOT_POSDEF: return "matrix not positive definite";
    case CHOLMOD_DSMALL: return "tiny diagonal entry in the factor";
    default: return "CHOLMOD status " + std::to_string(status);
  }
}

}  // namespace

struct CholmodSolver::Impl {
  cholmod_common common;
  cholmod_sparse matrix;             // header over pattern arrays below (the analysis' input)
  std::vector<int> column_starts;
  std::vector<int> row_indices;
  // tril(P A Pᵀ), the matrix CHOLMOD's supernodal numeric factorisation reads, kept for the
  // life of the analysis: cholmod_factorize would build it afresh (and allocate it) every time.
  cholmod_sparse permuted;
  std::vector<int> permuted_starts;
  std::vector<int> permuted_rows;
  std::vector<double> permuted_values;
  std::vector<int> to_permuted;      // entry k of A's upper triangle → its slot in permuted_values
  cholmod_factor* factor = nullptr;
  bool factor_valid = false;
  double shift = 0;
  double flops = 0;  // of one numeric factorisation, from the symbolic analysis
  Ordering ordering = Ordering::Automatic;
  // Solve workspaces kept between calls (cholmod_solve2 reuses them).
  mutable cholmod_dense* x = nullptr;
  mutable cholmod_dense* y = nullptr;
  mutable cholmod_dense* e = nullptr;

  Impl() {
    use_large_pages_for_cholmod();
    cholmod_start(&common);
    common.print = 0;               // never print; failures are reported through SolveError
    common.error_handler = nullptr;
    common.supernodal = CHOLMOD_SUPERNODAL;
    std::memset(&matrix, 0, sizeof(matrix));
    std::memset(&permuted, 0, sizeof(permuted));
  }
  ~Impl() {
    release_factor();
    cholmod_finish(&common);
  }
  void release_factor() {
    if (factor) cholmod_free_factor(&factor, &common);
    if (x) cholmod_free_dense(&x, &common);
    if (y) cholmod_free_dense(&y, &common);
    if (e) cholmod_free_dense(&e, &common);
    factor_valid = false;
  }
  void build_permuted_pattern();
  void check(const char* what) const {
    if (common.status < 0) throw SolveError(std::string("CHOLMOD ") + what + ": " + status_text(common.status));
  }
};

/// Pattern of tril(P A Pᵀ) from A's upper triangle and the factor's permutation (entry (i, j) of
/// A lands at row max(p⁻¹i, p⁻¹j) of column min(p⁻¹i, p⁻¹j)); rows sorted within each column.
void CholmodSolver::Impl::build_permuted_pattern() {
  const int n = int(factor->n);
  const int* perm = static_cast<const int*>(factor->Perm);
  std::vector<int> inverse(std::size_t(n), 0);
  for (int k = 0; k < n; ++k) inverse[std::size_t(perm[k])] = k;
  const std::size_t nnz = row_indices.size();
  std::vector<int> target_column(nnz), target_row(nnz);
  permuted_starts.assign(std::size_t(n) + 1, 0);
  for (int j = 0; j < n; ++j)
    for (int k = column_starts[std::size_t(j)]; k < column_starts[std::size_t(j) + 1]; ++k) {
      const int a = inverse[std::size_t(row_indices[std::size_t(k)])], b = inverse[std::size_t(j)];
      target_column[std::size_t(k)] = std::min(a, b);
      target_row[std::size_t(k)] = std::max(a, b);
      ++permuted_starts[std::size_t(target_column[std::size_t(k)]) + 1];
    }
  for (int j = 0; j < n; ++j) permuted_starts[std::size_t(j) + 1] += permuted_starts[std::size_t(j)];
  // Counting sort by row, then a stable placement by column: rows come out sorted per column.
  std::vector<int> by_row(nnz), row_starts(std::size_t(n) + 1, 0);
  for (std::size_t k = 0; k < nnz; ++k) ++row_starts[std::size_t(target_row[k]) + 1];
  for (int i = 0; i < n; ++i) row_starts[std::size_t(i) + 1] += row_starts[std::size_t(i)];
  for (std::size_t k = 0; k < nnz; ++k) by_row[std::size_t(row_starts[std::size_t(target_row[k])]++)] = int(k);
  std::vector<int> next(permuted_starts.begin(), permuted_starts.end() - 1);
  permuted_rows.assign(nnz, 0);
  to_permuted.assign(nnz, 0);
  for (const int k : by_row) {
    const int slot = next[std::size_t(target_column[std::size_t(k)])]++;
    permuted_rows[std::size_t(slot)] = target_row[std::size_t(k)];
    to_permuted[std::size_t(k)] = slot;
  }
  permuted_values = std::vector<double>();
  permuted_values.reserve(nnz);  // advised before its pages are first touched
  advise_large_pages(permuted_values.data(), nnz * sizeof(double));
  permuted_values.assign(nnz, 0.0);
  permuted.nrow = permuted.ncol = std::size_t(n);
  permuted.nzmax = nnz;
  permuted.p = permuted_starts.data();
  permuted.i = permuted_rows.data();
  permuted.x = permuted_values.data();
  permuted.stype = -1;  // lower triangle stored
  permuted.itype = CHOLMOD_INT;
  permuted.xtype = CHOLMOD_REAL;
  permuted.dtype = CHOLMOD_DOUBLE;
  permuted.sorted = 1;
  permuted.packed = 1;
}

Ordering choose_ordering(int n) { return n < kMetisFromDofs ? Ordering::Amd : Ordering::Metis; }

CholmodSolver::CholmodSolver(Ordering ordering) : m_impl(std::make_unique<Impl>()) {
  m_impl->ordering = ordering;
}
CholmodSolver::~CholmodSolver() = default;
CholmodSolver::CholmodSolver(CholmodSolver&&) noexcept = default;
CholmodSolver& CholmodSolver::operator=(CholmodSolver&&) noexcept = default;

void CholmodSolver::analyze(int n, const std::vector<int>& column_starts,
                            const std::vector<int>& row_indices) {
  Impl& s = *m_impl;
  s.release_factor();
  if (n <= 0) throw SolveError("CHOLMOD analyze: the system has no unknowns (every vertex is fixed)");
  if (int(column_starts.size()) != n + 1 || std::size_t(column_starts.back()) != row_indices.size())
    throw InternalError("CHOLMOD analyze: inconsistent sparsity pattern");
  s.column_starts = column_starts;
  s.row_indices = row_indices;
  cholmod_sparse& A = s.matrix;
  A.nrow = A.ncol = std::size_t(n);
  A.nzmax = row_indices.size();
  A.p = s.column_starts.data();
  A.i = s.row_indices.data();
  A.nz = nullptr;
  A.x = nullptr;
  A.z = nullptr;
  A.stype = 1;  // upper triangle stored
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_PATTERN;  // analysis needs the pattern only
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  const Ordering ordering = s.ordering == Ordering::Automatic ? choose_ordering(n) : s.ordering;
  s.common.nmethods = 1;
  s.common.method[0].ordering = ordering == Ordering::Amd     ? CHOLMOD_AMD
                                : ordering == Ordering::Metis ? CHOLMOD_METIS
                                                              : CHOLMOD_NESDIS;
  s.common.postorder = 1;
  {
    // METIS (CHOLMOD_METIS and NESDIS) draws its random numbers from one process-wide generator
    // (GKlib's), reseeded at each call: two analyses at once interleave its draws — a data race —
    // and each gets an ordering that depends on the other's timing. Orderings change the factor's
    // rounding, and the periodic cell problems amplify it: two tool cells homogenised side by side
    // read their bending stiffness 2e-8 apart from the same cells one after the other; with the
    // analyses one at a time they agree to the last bit. AMD has no such state.
    static std::mutex metis_mutex;
    std::unique_lock lock(metis_mutex, std::defer_lock);
    if (ordering != Ordering::Amd) lock.lock();
    s.factor = cholmod_analyze(&A, &s.common);
  }
  s.check("analyze");
  if (!s.factor) throw SolveError("CHOLMOD analyze failed: " + status_text(s.common.status));
  if (!s.factor->is_super) throw InternalError("CHOLMOD analyze: the factor is not supernodal");
  s.flops = s.common.fl;
  s.build_permuted_pattern();
}

bool CholmodSolver::factorize(const double* values, double shift) {
  Impl& s = *m_impl;
  if (!s.factor) throw InternalError("CHOLMOD factorize called before analyze");
  // What cholmod_factorize does for a supernodal factor, without its per-call permuted copy of A:
  // the values go into the kept tril(P A Pᵀ) and the numeric factorisation reads that.
  double* permuted = s.permuted_values.data();
  const int* slot = s.to_permuted.data();
  const std::size_t nnz = s.to_permuted.size();
  for (std::size_t k = 0; k < nnz; ++k) permuted[slot[k]] = values[k];
  double beta[2] = {shift, 0.0};
  s.factor_valid = false;
  set_factorization_threads(s.flops);
  const int ok = cholmod_super_numeric(&s.permuted, nullptr, beta, s.factor, &s.common);
  s.check("factorize");
  if (!ok) throw SolveError("CHOLMOD factorize failed: " + status_text(s.common.status));
  if (s.common.status == CHOLMOD_NOT_POSDEF || s.factor->minor < s.factor->n) return false;
  s.factor_valid = true;
  s.shift = shift;
  return true;
}

void CholmodSolver::solve(const double* b, double* x) const {
  const Impl& s = *m_impl;
  if (!s.factor_valid) throw InternalError("CHOLMOD solve without a valid factor");
  cholmod_dense B;
  std::memset(&B, 0, sizeof(B));
  B.nrow = s.factor->n;
  B.ncol = 1;
  B.nzmax = s.factor->n;
  B.d = s.factor->n;
  B.x = const_cast<double*>(b);
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  auto& common = const_cast<cholmod_common&>(s.common);
  set_factorization_threads(s.flops);
  const int ok = cholmod_solve2(CHOLMOD_A, s.factor, &B, nullptr, &s.x, nullptr, &s.y, &s.e, &common);
  s.check("solve");
  if (!ok || !s.x) throw SolveError("CHOLMOD solve failed: " + status_text(s.common.status));
  const double* result = static_cast<const double*>(s.x->x);
  std::copy(result, result + s.factor->n, x);
}

int CholmodSolver::size() const { return m_impl->factor ? int(m_impl->factor->n) : 0; }
bool CholmodSolver::analyzed() const { return m_impl->factor != nullptr; }
bool CholmodSolver::has_factor() const { return m_impl->factor_valid; }
double CholmodSolver::shift() const { return m_impl->shift; }

double CholmodSolver::rcond() const {
  if (!m_impl->factor_valid) return 0;
  return cholmod_rcond(m_impl->factor, &m_impl->common);
}

long CholmodSolver::factor_nonzeros() const {
  if (!m_impl->factor) return 0;
  return long(m_impl->common.lnz);
}

std::string CholmodSolver::ordering() const {
  if (!m_impl->factor) return "none";
  switch (m_impl->factor->ordering) {
    case CHOLMOD_NATURAL: return "natural";
    case CHOLMOD_GIVEN: return "given";
    case CHOLMOD_AMD: return "amd";
    case CHOLMOD_METIS: return "metis";
    case CHOLMOD_NESDIS: return "nesdis";
    case CHOLMOD_COLAMD: return "colamd";
    case CHOLMOD_POSTORDERED: return "postordered";
    default: return "unknown";
  }
}

double CholmodSolver::factorization_flops() const { return m_impl->factor ? m_impl->flops : 0.0; }

bool CholmodSolver::supernodal() const { return m_impl->factor && m_impl->factor->is_super; }

}  // namespace cutwork::solvers
