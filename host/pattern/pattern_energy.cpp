#include "host/pattern/pattern_energy.h"

#include "host/core/internal_error.h"

namespace cutwork {

PatternEnergy::PatternEnergy(const PatternSurface& surface, const PatternEnergySettings& settings,
                             const DetExemplar* exemplar)
    : m_surface(&surface), m_settings(settings), m_exemplar(exemplar) {
  if (settings.kind == PatternKind::Exemplar && !exemplar)
    throw InternalError("PatternEnergy: the exemplar objective needs an exemplar");
}

void PatternEnergy::rematch(const StencilLayout& layout) {
  if (m_settings.kind != PatternKind::Exemplar) return;
  m_matched = int(layout.size());
  m_image_sources.clear();
  const PatternMirror& mirror = m_surface->mirror();
  if (!mirror.any()) {
    m_hoods = det_match(*m_exemplar, *m_surface, layout);
    return;
  }
  // The layout and the images within a neighbourhood's radius of it; only the layout is matched.
  const double reach =
      m_exemplar->radius() * m_exemplar->settings().sigma * m_surface->sizing().max_value();
  StencilLayout with_images = layout;
  for (int k = 0; k < mirror.num_reflections(); ++k)
    for (int j = 0; j < int(layout.size()); ++j) {
      if (mirror.reach_of_image(layout[size_t(j)].position, k) > reach) continue;
      PlacedStencil image = layout[size_t(j)];
      image.position = mirror.image(image.position, k);
      with_images.push_back(image);
      m_image_sources.emplace_back(j, k);
    }
  m_hoods = det_match(*m_exemplar, *m_surface, with_images, m_matched);
}

int PatternEnergy::vote_types(StencilLayout& layout) const {
  if (m_image_sources.empty()) return det_vote_types(*m_exemplar, m_hoods, layout);
  std::vector<DetNeighborhood> hoods = m_hoods;
  for (DetNeighborhood& h : hoods)
    for (int& j : h.outputs)
      if (j >= m_matched) j = m_image_sources[size_t(j - m_matched)].first;
  return det_vote_types(*m_exemplar, hoods, layout);
}

double PatternEnergy::evaluate(const RowMatX3d& q, const Eigen::VectorXd& scales,
                               const Eigen::VectorXi& types, RowMatX3d* d_q,
                               Eigen::VectorXd* d_scales, PatternTerms* terms) const {
  const int S = int(q.rows());
  const PatternEnergySettings& st = m_settings;
  const double inv2 = 1.0 / (st.unit * st.unit);
  const bool grad = d_q || d_scales;

  // Projection and its Jacobian ∂c/∂q.
  RowMatX3d c(S, 3);
  std::vector<Eigen::Matrix3d> J(grad ? size_t(S) : 0);
  Eigen::VectorXd slack(S);
  PatternTerms t;
  for (int i = 0; i < S; ++i) {
    const Vec3 qi = q.row(i).transpose();
    FrameJacobian fj;
    const Frame fr = m_surface->frame(qi, grad ? &fj : nullptr);
    c.row(i) = fr.origin.transpose();
    if (grad) J[size_t(i)] = fj.d_origin;
    slack[i] = (qi - fr.origin).norm();
    t.tether += st.admissibility * st.tether * slack[i] * slack[i] * inv2;
  }

  RowMatX3d gc, gq;
  Eigen::VectorXd gs, part;
  if (grad) {
    gc = RowMatX3d::Zero(S, 3);
    gq = RowMatX3d::Zero(S, 3);
    gs = Eigen::VectorXd::Zero(S);
  }
  auto weighted = [&](double w, RowMatX3d* into, auto&& term) {
    RowMatX3d pq;
    Eigen::VectorXd ps;
    if (grad) {
      pq = RowMatX3d::Zero(S, 3);
      ps = Eigen::VectorXd::Zero(S);
    }
    const double v = term(grad ? &pq : nullptr, grad ? &ps : nullptr);
    if (grad) {
      *into += w * pq;
      gs += w * ps;
    }
    return w * v;
  };

  const bool packing = st.kind == PatternKind::Packing;
  const std::vector<PointPair> cand =
      packing_candidates(c, scales, st.safety, packing ? st.epsilon : 0.0, st.gap);
  // Symmetry planes: the images' pairs and the planes' terms (pattern_mirror.h).
  const PatternMirror& mirror = m_surface->mirror();
  const std::vector<ImagePair> image_cand =
      mirror.any() ? image_pairs(mirror, c, packing_cutoff(scales, st.safety, packing ? st.epsilon : 0.0, st.gap))
                   : std::vector<ImagePair>{};
  if (!packing) {
    t.det = weighted(1.0, &gc, [&](RowMatX3d* pq, Eigen::VectorXd* ps) {
      if (m_image_sources.empty()) return det_objective(*m_exemplar, m_hoods, c, scales, types, pq, ps);
      // The neighbourhoods hold images: evaluate on the layout and its images, then take the images'
      // gradients back through their reflections.
      if (S != m_matched) throw InternalError("PatternEnergy: evaluated on a layout it was not matched on");
      const int I = int(m_image_sources.size());
      RowMatX3d ca(S + I, 3);
      Eigen::VectorXd sa(S + I);
      Eigen::VectorXi ta(S + I);
      ca.topRows(S) = c;
      sa.head(S) = scales;
      ta.head(S) = types;
      for (int n = 0; n < I; ++n) {
        const auto [j, k] = m_image_sources[size_t(n)];
        ca.row(S + n) = mirror.image(c.row(j).transpose(), k).transpose();
        sa[S + n] = scales[j];
        ta[S + n] = types[j];
      }
      RowMatX3d ga;
      Eigen::VectorXd gsa;
      if (pq) {
        ga = RowMatX3d::Zero(S + I, 3);
        gsa = Eigen::VectorXd::Zero(S + I);
      }
      const double v = det_objective(*m_exemplar, m_hoods, ca, sa, ta, pq ? &ga : nullptr, pq ? &gsa : nullptr);
      if (pq) {
        *pq += ga.topRows(S);
        *ps += gsa.head(S);
        for (int n = 0; n < I; ++n) {
          const auto [j, k] = m_image_sources[size_t(n)];
          pq->row(j) += ga.row(S + n).cwiseProduct(mirror.flip(k).transpose());
          (*ps)[j] += gsa[S + n];
        }
      }
      return v;
    });
  }
  t.collision = weighted(st.admissibility * st.weights.collision, &gc, [&](RowMatX3d* pq, Eigen::VectorXd* ps) {
    return collision_objective(c, scales, st.safety, st.unit, cand, pq, ps, st.gap) +
           image_collision_objective(mirror, c, scales, st.safety, st.unit, image_cand, pq, ps, st.gap);
  });
  t.boundary = weighted(st.admissibility * st.weights.collision, &gq, [&](RowMatX3d* pq, Eigen::VectorXd* ps) {
    return boundary_collision_objective(q, scales, st.safety, st.unit, m_surface->boundary(), &slack,
                                        pq, ps, st.gap) +
           plane_collision_objective(mirror, q, scales, st.safety, st.unit, pq, ps, st.gap);
  });
  if (packing) {
    t.repulsion = weighted(st.weights.repulsion, &gc, [&](RowMatX3d* pq, Eigen::VectorXd*) {
      return repulsion_objective(c, st.epsilon, st.unit, cand, pq) +
             image_repulsion_objective(mirror, c, st.epsilon, st.unit, image_cand, pq);
    });
    t.growth = weighted(st.weights.growth, &gc, [&](RowMatX3d*, Eigen::VectorXd* ps) {
      return growth_objective(scales, st.unit, ps);
    });
  }
  if (grad) {
    for (int i = 0; i < S; ++i) {
      const Vec3 qi = q.row(i).transpose(), ci = c.row(i).transpose();
      // ∂|q − Π(q)|²/∂q = 2 (q − Π(q)) (the squared distance to the surface).
      const Vec3 g = J[size_t(i)].transpose() * gc.row(i).transpose() +
                     gq.row(i).transpose() + 2 * st.admissibility * st.tether * inv2 * (qi - ci);
      gq.row(i) = g.transpose();
    }
    if (d_q) *d_q = gq;
    if (d_scales) *d_scales = gs;
  }
  if (terms) *terms = t;
  return t.total();
}

double PatternEnergy::evaluate(const StencilLayout& layout, PatternTerms* terms) const {
  return evaluate(layout_positions(layout), layout_scales(layout), layout_types(layout), nullptr,
                  nullptr, terms);
}

}  // namespace cutwork
