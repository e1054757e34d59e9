#include "solvers/linear/block_assembly.h"

#include <algorithm>
#include <limits>

#include "host/core/error.h"

namespace cutwork::solvers {

BlockAssembly::BlockAssembly(int num_nodes, const std::vector<ElementNodes>& element_nodes)
    : m_num_nodes(num_nodes), m_nodes(element_nodes) {
  // Row blocks of every block column (upper triangle: row node ≤ column node).
  std::vector<std::vector<int>> rows(num_nodes);
  for (int n = 0; n < num_nodes; ++n) rows[n].push_back(n);
  for (const ElementNodes& nodes : m_nodes) {
    for (int a = 0; a < kMaxNodes; ++a) {
      for (int b = 0; b < kMaxNodes; ++b) {
        const int na = nodes[a], nb = nodes[b];
        if (na < 0 || nb < 0 || na >= nb) continue;
        rows[nb].push_back(na);
      }
    }
  }
  long nnz = 0;
  for (auto& r : rows) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    nnz += 9 * long(r.size()) - 3;  // 3 full-height columns minus the strict lower diagonal block
  }
  if (nnz > long(std::numeric_limits<int>::max()))
    throw SolveError("the model is too large for 32-bit sparse indices (" + std::to_string(nnz) +
                     " stored entries); use a coarser simulation mesh");

  m_column_starts.assign(3 * std::size_t(num_nodes) + 1, 0);
  m_row_indices.resize(std::size_t(nnz));
  int pos = 0;
  for (int n = 0; n < num_nodes; ++n) {
    for (int d = 0; d < 3; ++d) {
      m_column_starts[3 * n + d] = pos;
      for (int r : rows[n]) {
        const int nr = r == n ? d + 1 : 3;
        for (int c = 0; c < nr; ++c) m_row_indices[pos++] = 3 * r + c;
      }
    }
  }
  m_column_starts[3 * num_nodes] = pos;

  m_block_base.resize(m_nodes.size());
  for (std::size_t e = 0; e < m_nodes.size(); ++e) {
    const ElementNodes& nodes = m_nodes[e];
    auto& base = m_block_base[e];
    base.fill(-1);
    for (int a = 0; a < kMaxNodes; ++a) {
      for (int b = 0; b < kMaxNodes; ++b) {
        const int na = nodes[a], nb = nodes[b];
        if (na < 0 || nb < 0 || na > nb) continue;
        const auto& r = rows[nb];
        const int rank = int(std::lower_bound(r.begin(), r.end(), na) - r.begin());
        base[a * kMaxNodes + b] = 3 * rank;
      }
    }
  }

  colour_elements();
  colour_chunks();
}

void BlockAssembly::colour_elements() {
  // Colouring by passes: each pass takes, in index order, every uncoloured element whose nodes are
  // untouched in this pass. Deterministic, and the colour count stays near the largest number of
  // elements that share a node.
  std::vector<int> node_pass(m_num_nodes, -1);
  std::vector<int> pending;
  for (std::size_t e = 0; e < m_nodes.size(); ++e) {
    bool has_dof = false;
    for (int n : m_nodes[e]) has_dof |= n >= 0;
    (has_dof ? pending : m_uncoloured).push_back(int(e));
  }
  for (int pass = 0; !pending.empty(); ++pass) {
    std::vector<int> members;
    std::vector<int> rest;
    for (int e : pending) {
      bool free = true;
      for (int n : m_nodes[e])
        if (n >= 0 && node_pass[n] == pass) free = false;
      if (!free) {
        rest.push_back(e);
        continue;
      }
      for (int n : m_nodes[e])
        if (n >= 0) node_pass[n] = pass;
      members.push_back(e);
    }
    m_colours.push_back(std::move(members));
    pending.swap(rest);
  }
}

void BlockAssembly::colour_chunks() {
  // The same passes over chunks: a chunk joins the pass when none of its nodes is taken in it.
  const int ne = num_elements();
  std::vector<Chunk> pending;
  for (int begin = 0; begin < ne; begin += kChunkElements) pending.push_back({begin, std::min(ne, begin + kChunkElements)});
  std::vector<int> node_pass(m_num_nodes, -1);
  for (int pass = 0; !pending.empty(); ++pass) {
    std::vector<Chunk> members, rest;
    for (const Chunk& c : pending) {
      bool free = true;
      for (int e = c.begin; e < c.end && free; ++e)
        for (int n : m_nodes[e])
          if (n >= 0 && node_pass[n] == pass) free = false;
      if (!free) {
        rest.push_back(c);
        continue;
      }
      for (int e = c.begin; e < c.end; ++e)
        for (int n : m_nodes[e])
          if (n >= 0) node_pass[n] = pass;
      members.push_back(c);
    }
    m_chunk_colours.push_back(std::move(members));
    pending.swap(rest);
  }
}

}  // namespace cutwork::solvers
