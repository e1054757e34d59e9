#pragma once
/// Assembly of a symmetric sparse matrix over nodes with 3 DOFs each, from elements that touch up to
/// six nodes, with everything that depends on topology alone built once:
///   - the upper-triangular CSC pattern (what CHOLMOD's symmetric stype = 1 mode reads),
///   - per element, the value slot of each of its 3×3 blocks (the element→slot scatter map),
///   - a colouring of the elements such that no two elements of one colour share a node, and one of
///     chunks of consecutive elements (chunk_colours(), what the shell assembly uses: locality).
/// Refilling values is then a loop over colours with a parallel loop over each colour's chunks,
/// each scattering straight into the value array: no races, no triplets, no sort, and the sum in
/// every slot is taken in the same order whatever the number of threads (bitwise reproducible).
///
/// DOF numbering: node n owns DOFs 3n, 3n+1, 3n+2 (x, y, z). Nodes are the free (unsupported)
/// vertices; an element refers to a position that is not a DOF (a fixed vertex, a ghost point, an
/// unused slot) with node id −1, and its rows and columns are simply not scattered — the fixed DOFs
/// are eliminated, the assembled matrix is the reduced one.
#include <algorithm>
#include <array>
#include <initializer_list>
#include <vector>

#include <Eigen/Core>

namespace cutwork::solvers {

class BlockAssembly {
 public:
  static constexpr int kMaxNodes = 6;
  using ElementNodes = std::array<int, kMaxNodes>;
  /// Node ids of an element with fewer than kMaxNodes nodes: the rest are −1 (no DOF). Use this
  /// rather than a braced list, whose missing entries would be 0 — node 0.
  static ElementNodes nodes(std::initializer_list<int> ids) {
    ElementNodes n;
    n.fill(-1);
    std::copy(ids.begin(), ids.end(), n.begin());
    return n;
  }

  BlockAssembly() = default;
  /// num_nodes: number of free nodes (#DOF = 3·num_nodes). element_nodes: per element its node ids
  /// in the element's local DOF order, −1 where a local vertex is not a DOF. Every node gets its
  /// diagonal block even when no element touches it.
  BlockAssembly(int num_nodes, const std::vector<ElementNodes>& element_nodes);

  int num_nodes() const { return m_num_nodes; }
  int num_dofs() const { return 3 * m_num_nodes; }
  int num_elements() const { return int(m_nodes.size()); }
  /// Stored entries of the upper triangle (diagonal included).
  long num_nonzeros() const { return long(m_row_indices.size()); }
  /// CSC column starts (#DOF + 1) and row indices (nnz) of the upper triangle, rows sorted.
  const std::vector<int>& column_starts() const { return m_column_starts; }
  const std::vector<int>& row_indices() const { return m_row_indices; }

  /// Elements grouped by colour; elements without any DOF are in no colour.
  const std::vector<std::vector<int>>& colours() const { return m_colours; }
  /// Elements without any DOF (they add energy but nothing to the matrix or the gradient).
  const std::vector<int>& uncoloured() const { return m_uncoloured; }

  /// A run of consecutive elements [begin, end) (kChunkElements of them, fewer at the end).
  struct Chunk {
    int begin = 0, end = 0;
  };
  static constexpr int kChunkElements = 64;
  /// Every element, cut into chunks of consecutive indices and the chunks grouped by colour: no
  /// two chunks of one colour share a node. What the assembly loops over: one colour at a time,
  /// its chunks in parallel, each chunk's elements in index order. Consecutive elements of a mesh
  /// touch nearby nodes, so a chunk's scatters stay in a few cached columns, where a colour of
  /// single elements is spread over the whole matrix (every colour would stream through all of it).
  /// The order of the contributions to every slot is fixed by the chunks, whatever the thread count.
  const std::vector<std::vector<Chunk>>& chunk_colours() const { return m_chunk_colours; }

  /// Adds the local matrix of element e (3K×3K in the element's local DOF order, symmetric; only its
  /// blocks that land in the upper triangle are read) into values (nnz).
  template <int K>
  void scatter_matrix(int e, const Eigen::Matrix<double, 3 * K, 3 * K>& local, double* values) const {
    const ElementNodes& nodes = m_nodes[e];
    const auto& base = m_block_base[e];
    for (int a = 0; a < K; ++a) {
      if (nodes[a] < 0) continue;
      for (int b = 0; b < K; ++b) {
        const int slot0 = base[a * kMaxNodes + b];
        if (slot0 < 0) continue;
        const int column = 3 * nodes[b];
        const int rows = nodes[a] == nodes[b] ? -1 : 3;  // diagonal block: upper part only
        for (int d = 0; d < 3; ++d) {
          double* col = values + m_column_starts[column + d] + slot0;
          const int nr = rows < 0 ? d + 1 : 3;
          for (int c = 0; c < nr; ++c) col[c] += local(3 * a + c, 3 * b + d);
        }
      }
    }
  }

  /// Adds the local vector of element e (3K) into the DOF vector `vec` (#DOF).
  template <int K>
  void scatter_vector(int e, const Eigen::Matrix<double, 3 * K, 1>& local, double* vec) const {
    const ElementNodes& nodes = m_nodes[e];
    for (int a = 0; a < K; ++a) {
      if (nodes[a] < 0) continue;
      for (int c = 0; c < 3; ++c) vec[3 * nodes[a] + c] += local[3 * a + c];
    }
  }

 private:
  int m_num_nodes = 0;
  std::vector<ElementNodes> m_nodes;
  /// Per element, per local block (a, b): the offset of row 3·node_a within each of the three
  /// columns of block column node_b, or −1 when the block is not stored (a DOF-less node, or a block
  /// below the diagonal, whose transpose is stored instead).
  std::vector<std::array<int, kMaxNodes * kMaxNodes>> m_block_base;
  std::vector<int> m_column_starts;
  std::vector<int> m_row_indices;
  std::vector<std::vector<int>> m_colours;
  std::vector<int> m_uncoloured;
  std::vector<std::vector<Chunk>> m_chunk_colours;

  void colour_elements();
  void colour_chunks();
};

}  // namespace cutwork::solvers
