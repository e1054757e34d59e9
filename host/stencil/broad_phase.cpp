#include "host/stencil/broad_phase.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "host/core/error.h"
#include "host/core/internal_error.h"

namespace cutwork {

BroadPhase::BroadPhase(const FaceBvh& bvh, BroadPhaseOptions options)
    : m_bvh(&bvh), m_options(options) {
  if (!(std::isfinite(options.margin) && options.margin >= 0))
    throw InputError("broad phase: margin must be finite and ≥ 0");
  if (!(std::isfinite(options.slack) && options.slack >= 0))
    throw InputError("broad phase: slack must be finite and ≥ 0");
  clear();
}

void BroadPhase::clear() {
  m_faces_of.clear();
  m_query_center.clear();
  m_query_radius.clear();
  m_pairs.clear();
  m_stencil_pairs.clear();
  m_stencil_offsets.assign(1, 0);
  const int faces = m_bvh->mesh() ? m_bvh->mesh()->num_faces() : 0;
  m_face_offsets.assign(size_t(faces) + 1, 0);
}

int BroadPhase::update(std::span<const Vec3> centers, std::span<const double> scales) {
  if (centers.size() != scales.size())
    throw InternalError("broad phase: " + std::to_string(centers.size()) + " centres but " +
                     std::to_string(scales.size()) + " scales");
  const size_t n = centers.size();
  if (m_faces_of.size() != n) {
    clear();
    m_faces_of.resize(n);
    m_query_center.assign(n, Vec3::Zero());
    m_query_radius.assign(n, -1.0);  // invalid: forces a query
  }
  std::vector<int>& stale = m_stale;
  stale.clear();
  for (size_t i = 0; i < n; ++i) {
    const double needed = scales[i] * (1 + m_options.margin);
    if (!(m_query_radius[i] >= 0) ||
        !((centers[i] - m_query_center[i]).norm() + needed <= m_query_radius[i]))
      stale.push_back(int(i));
  }
  tbb::parallel_for(size_t(0), stale.size(), [&](size_t k) {
    const size_t i = size_t(stale[k]);
    const double radius = scales[i] * (1 + m_options.margin) * (1 + m_options.slack);
    m_bvh->faces_in_ball(centers[i], radius, m_faces_of[i]);
    m_query_center[i] = centers[i];
    m_query_radius[i] = radius;
  });
  if (!stale.empty() || m_pairs.empty()) assemble();
  return int(stale.size());
}

void BroadPhase::assemble() {
  // Counting sort by face; visiting stencils in ascending order keeps each face's pairs sorted
  // by stencil, so the order (hence the fill reduction) is deterministic.
  const size_t faces = m_face_offsets.size() - 1, stencils = m_faces_of.size();
  std::fill(m_face_offsets.begin(), m_face_offsets.end(), 0);
  m_stencil_offsets.assign(stencils + 1, 0);
  for (size_t s = 0; s < stencils; ++s) {
    for (int f : m_faces_of[s]) ++m_face_offsets[size_t(f) + 1];
    m_stencil_offsets[s + 1] = m_stencil_offsets[s] + int32_t(m_faces_of[s].size());
  }
  for (size_t f = 0; f < faces; ++f) m_face_offsets[f + 1] += m_face_offsets[f];
  const size_t total = size_t(m_face_offsets[faces]);
  m_pairs.resize(total);
  m_stencil_pairs.resize(total);
  std::vector<int32_t>& cursor = m_cursor;
  cursor.assign(m_face_offsets.begin(), m_face_offsets.end() - 1);
  for (size_t s = 0; s < stencils; ++s) {
    int32_t j = m_stencil_offsets[s];
    for (int f : m_faces_of[s]) {
      const int32_t i = cursor[size_t(f)]++;
      m_pairs[size_t(i)] = {int32_t(s), int32_t(f)};
      m_stencil_pairs[size_t(j++)] = i;
    }
  }
}

std::vector<kernels::ClipPair> candidate_pairs_brute_force(const SurfaceMesh& mesh,
                                                           std::span<const Vec3> centers,
                                                           std::span<const double> scales,
                                                           double margin) {
  std::vector<kernels::ClipPair> pairs;
  std::vector<int> faces;
  for (size_t s = 0; s < centers.size(); ++s) {
    faces_in_ball_brute_force(mesh, centers[s], scales[s] * (1 + margin), faces);
    for (int f : faces) pairs.push_back({int32_t(s), int32_t(f)});
  }
  std::sort(pairs.begin(), pairs.end(), [](const kernels::ClipPair& a, const kernels::ClipPair& b) {
    return a.face < b.face || (a.face == b.face && a.stencil < b.stencil);
  });
  return pairs;
}

}  // namespace cutwork
