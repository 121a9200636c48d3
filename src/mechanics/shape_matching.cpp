// ClusteringEngine, ShapeMatching and PositionBasedDynamicsProjectiveConstraint (Vec3d), in SOFA's
// order of operations (docs/components/shape_matching.md).
#include "penalty/mechanics/shape_matching.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

namespace penalty {

namespace {

using Clusters = std::vector<std::vector<PointId>>;
using Neighbours = std::vector<std::vector<PointId>>;

double distance(const Vec3& a, const Vec3& b) { return (a - b).norm(); }

/// ClusteringEngine::Voronoi: each point's distance to its nearest seed (only ever lowered) and
/// that seed's rank.
void euclidean_voronoi(const std::vector<Vec3>& x, const std::vector<PointId>& seeds, std::vector<double>& dist,
                       std::vector<PointId>& voronoi) {
    for (std::size_t i = 0; i < x.size(); ++i)
        for (std::size_t j = 0; j < seeds.size(); ++j) {
            const double d = distance(x[i], x[static_cast<std::size_t>(seeds[j])]);
            if (d < dist[i]) {
                dist[i] = d;
                voronoi[i] = static_cast<PointId>(j);
            }
        }
}

/// ClusteringEngine::dijkstra: geodesic distances along the edges from every seed at once, with
/// SOFA's priority queue (a set ordered by distance, then point index).
void geodesic_voronoi(const std::vector<Vec3>& x, const Neighbours& around, const std::vector<PointId>& seeds,
                      std::vector<double>& dist, std::vector<PointId>& voronoi) {
    std::set<std::pair<double, PointId>> queue;
    for (std::size_t i = 0; i < seeds.size(); ++i) {
        const auto s = static_cast<std::size_t>(seeds[i]);
        queue.insert({0.0, seeds[i]});
        dist[s] = 0;
        voronoi[s] = static_cast<PointId>(i);
    }
    while (!queue.empty()) {
        const auto v = static_cast<std::size_t>(queue.begin()->second);
        queue.erase(queue.begin());
        if (v >= around.size()) continue;
        for (const PointId n : around[v]) {
            const auto v2 = static_cast<std::size_t>(n);
            const double d = dist[v] + distance(x[v], x[v2]);
            if (dist[v2] > d) {
                if (const auto it = queue.find({dist[v2], n}); it != queue.end()) queue.erase(it);
                voronoi[v2] = voronoi[v];
                dist[v2] = d;
                queue.insert({d, n});
            }
        }
    }
}

/// ClusteringEngine::farthestPointSampling: seeds from point 0, each next one the farthest point
/// (first in index order) from the seeds so far; then the final Voronoi regions.
void farthest_point_sampling(const std::vector<Vec3>& x, const Neighbours* around, int number,
                             std::vector<PointId>& seeds, std::vector<PointId>& voronoi) {
    const std::size_t n = x.size();
    // SOFA casts the number to unsigned: any negative other than -1 (handled before) means all
    const std::size_t wanted = number < 0 ? n : std::min(static_cast<std::size_t>(number), n);
    seeds.assign(1, 0);
    voronoi.assign(n, 0);
    std::vector<double> dist(n, std::numeric_limits<double>::max());
    const auto regions = [&] {
        if (around != nullptr) geodesic_voronoi(x, *around, seeds, dist, voronoi);
        else euclidean_voronoi(x, seeds, dist, voronoi);
    };
    while (seeds.size() < wanted) {
        regions();
        double dmax = 0;
        PointId imax = 0;
        for (std::size_t i = 0; i < n; ++i)
            if (dist[i] > dmax) {
                dmax = dist[i];
                imax = static_cast<PointId>(i);
            }
        if (dmax == 0) break;
        seeds.push_back(imax);
    }
    regions();
}

/// ClusteringEngine::AddNeighborhoodFromNeighborhood, as a loop: the ring grown last is expanded
/// along the edges; a neighbour joins when it is within `radius` of the seed, or when the point it
/// is reached from lies in the seed's Voronoi region (so the region and one ring around it join).
void grow_along_edges(const std::vector<Vec3>& x, const Neighbours& around, const std::vector<PointId>& voronoi,
                      PointId rank, double radius, std::vector<PointId>& cluster) {
    const Vec3& seed = x[static_cast<std::size_t>(cluster.front())];
    std::vector<char> member(x.size(), 0);
    for (PointId p : cluster) member[static_cast<std::size_t>(p)] = 1;
    std::vector<PointId> last{cluster.front()}, next;
    while (!last.empty()) {
        next.clear();
        for (const PointId from : last) {
            const auto f = static_cast<std::size_t>(from);
            if (f >= around.size()) continue;
            for (const PointId pt : around[f]) {
                const auto p = static_cast<std::size_t>(pt);
                if ((voronoi[f] == rank || distance(seed, x[p]) < radius) && member[p] == 0) {
                    member[p] = 1;
                    cluster.push_back(pt);
                    next.push_back(pt);
                }
            }
        }
        last.swap(next);
    }
}

/// The members of each seed's cluster without a topology (ClusteringEngine::doUpdate's else branch).
void gather_by_radius(const std::vector<Vec3>& x, const std::vector<PointId>& seeds, const ClusteringParameters& params,
                      const std::vector<Vec3>& fixed, Clusters& clusters) {
    for (std::size_t j = 0; j < x.size(); ++j) {
        bool inserted = false;
        for (std::size_t i = 0; i < seeds.size(); ++i)
            if (static_cast<PointId>(j) != seeds[i] &&
                distance(x[j], x[static_cast<std::size_t>(seeds[i])]) < params.radius) {
                clusters[i].push_back(static_cast<PointId>(j));
                inserted = true;
            }
        if (inserted) continue;
        // a point in no cluster joins the nearest other seed's (a lone seed too, as SOFA)
        double dmin = std::numeric_limits<double>::max();
        int imin = -1;
        for (std::size_t i = 0; i < seeds.size(); ++i)
            if (static_cast<PointId>(j) != seeds[i]) {
                const double d = distance(x[j], x[static_cast<std::size_t>(seeds[i])]);
                if (d < dmin) {
                    dmin = d;
                    imin = static_cast<int>(i);
                }
            }
        if (imin != -1) clusters[static_cast<std::size_t>(imin)].push_back(static_cast<PointId>(j));
    }
    for (std::size_t j = 0; j < fixed.size(); ++j)
        for (std::size_t i = 0; i < seeds.size(); ++i)
            if (distance(fixed[j], x[static_cast<std::size_t>(seeds[i])]) < params.fixed_radius)
                clusters[i].push_back(static_cast<PointId>(j + x.size()));
}

double one_norm(const Mat3& a) {  // largest column sum of |a|
    double norm = 0;
    for (int c = 0; c < 3; ++c) norm = std::max(norm, std::abs(a(0, c)) + std::abs(a(1, c)) + std::abs(a(2, c)));
    return norm;
}
double inf_norm(const Mat3& a) {  // largest row sum of |a|
    double norm = 0;
    for (int r = 0; r < 3; ++r) norm = std::max(norm, std::abs(a(r, 0)) + std::abs(a(r, 1)) + std::abs(a(r, 2)));
    return norm;
}
Vec3 sofa_cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

}  // namespace

Clusters clustering_engine(const std::vector<Vec3>& positions, const Neighbours* vertices_around_vertex,
                           const ClusteringParameters& params, const std::vector<Vec3>& fixed_positions) {
    if (positions.empty()) return {};
    const Neighbours* around = params.use_topology ? vertices_around_vertex : nullptr;
    if (around != nullptr)
        for (const auto& list : *around)
            for (PointId p : list)
                if (p < 0 || static_cast<std::size_t>(p) >= positions.size())
                    throw std::invalid_argument("ClusteringEngine: the topology names point " + std::to_string(p) +
                                                " of " + std::to_string(positions.size()) + " positions");
    std::vector<PointId> seeds, voronoi;
    if (params.number == -1) {
        for (std::size_t i = 0; i < positions.size(); ++i) {
            seeds.push_back(static_cast<PointId>(i));
            voronoi.push_back(static_cast<PointId>(i));
        }
    } else {
        farthest_point_sampling(positions, around, params.number, seeds, voronoi);
    }
    Clusters clusters(seeds.size());
    for (std::size_t i = 0; i < seeds.size(); ++i) clusters[i].push_back(seeds[i]);
    if (around != nullptr) {
        for (std::size_t i = 0; i < seeds.size(); ++i)
            grow_along_edges(positions, *around, voronoi, static_cast<PointId>(i), params.radius, clusters[i]);
    } else {
        gather_by_radius(positions, seeds, params, fixed_positions, clusters);
    }
    return clusters;
}

Mat3 sofa_polar_rotation(const Mat3& m) {
    Mat3 mk = m.transpose();
    double m_one = one_norm(mk), m_inf = inf_norm(mk), e_one = 0;
    // SOFA iterates without a limit; the scaled Newton iteration converges quadratically (a few
    // passes), so the cap only guards against a non-finite input that would never settle
    constexpr int kMaxPasses = 100;
    int passes = 0;
    do {
        Mat3 adj;  // rows: cross products of Mk's rows (Mk's adjugate, transposed)
        adj.row(0) = sofa_cross(mk.row(1), mk.row(2));
        adj.row(1) = sofa_cross(mk.row(2), mk.row(0));
        adj.row(2) = sofa_cross(mk.row(0), mk.row(1));
        const double det = mk(0, 0) * adj(0, 0) + mk(0, 1) * adj(0, 1) + mk(0, 2) * adj(0, 2);
        if (det == 0.0) break;  // SOFA warns and keeps Mk as it is
        const double adj_one = one_norm(adj), adj_inf = inf_norm(adj);
        const double gamma = std::sqrt(std::sqrt((adj_one * adj_inf) / (m_one * m_inf)) / std::fabs(det));
        const double g1 = gamma * 0.5;
        const double g2 = 0.5 / (gamma * det);
        Mat3 ek = mk;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) mk(r, c) = mk(r, c) * g1 + adj(r, c) * g2;
        ek -= mk;
        e_one = one_norm(ek);
        m_one = one_norm(mk);
        m_inf = inf_norm(mk);
    } while (e_one > m_one * 1e-8 && ++passes < kMaxPasses);
    return mk.transpose();
}

ShapeMatching::ShapeMatching(Clusters clusters, std::vector<Vec3> rest_positions, const ShapeMatchingParameters& params,
                             std::vector<Vec3> fixed_rest_positions, std::vector<Vec3> fixed_positions)
    : clusters_(std::move(clusters)),
      rest_(std::move(rest_positions)),
      params_(params),
      fixed_rest_(std::move(fixed_rest_positions)),
      fixed_(std::move(fixed_positions)) {
    const std::size_t nbp = rest_.size();
    if (fixed_.size() != fixed_rest_.size())
        throw std::invalid_argument("ShapeMatching: fixedPosition has " + std::to_string(fixed_.size()) +
                                    " points and fixedPosition0 " + std::to_string(fixed_rest_.size()));
    for (std::size_t i = 0; i < clusters_.size(); ++i) {
        if (clusters_[i].empty())
            throw std::invalid_argument("ShapeMatching: cluster " + std::to_string(i) + " is empty");
        for (PointId p : clusters_[i])
            if (p < 0 || static_cast<std::size_t>(p) >= nbp + fixed_rest_.size())
                throw std::invalid_argument("ShapeMatching: cluster " + std::to_string(i) + " names point " +
                                            std::to_string(p) + " of " + std::to_string(nbp + fixed_rest_.size()));
    }
    // ShapeMatching::doUpdate's rest data: Xcm0 = Σw x0 / W, Qx = Σw x0x0ᵀ − W·Xcm0Xcm0ᵀ
    const std::size_t nbc = clusters_.size();
    rest_centres_.assign(nbc, Vec3::Zero());
    inverse_covariance_.assign(nbc, Mat3::Zero());
    weights_.assign(nbc, 0.0);
    clusters_of_point_.assign(nbp, 0);
    for (std::size_t i = 0; i < nbc; ++i) {
        Mat3 qx = Mat3::Zero();
        for (PointId id : clusters_[i]) {
            const auto k = static_cast<std::size_t>(id);
            const bool mechanical = k < nbp;
            const Vec3& p0 = mechanical ? rest_[k] : fixed_rest_[k - nbp];
            const double w = mechanical ? 1.0 : params_.fixed_weight;
            rest_centres_[i] += p0 * w;
            qx += (p0 * p0.transpose()) * w;
            weights_[i] += w;
            if (mechanical) ++clusters_of_point_[k];
        }
        rest_centres_[i] /= weights_[i];
        qx -= (rest_centres_[i] * rest_centres_[i].transpose()) * weights_[i];
        if (params_.affine_ratio != 0.0) {
            if (qx.determinant() == 0.0)
                throw std::invalid_argument(
                    "ShapeMatching: cluster " + std::to_string(i) +
                    " is flat (its rest covariance cannot be inverted), so affineRatio must be 0");
            inverse_covariance_[i] = qx.inverse();
        }
    }
}

void ShapeMatching::targets(const std::vector<Vec3>& current, std::vector<Vec3>& target) const {
    const std::size_t nbp = rest_.size();
    if (current.size() != nbp)
        throw std::invalid_argument("ShapeMatching: " + std::to_string(current.size()) + " positions for " +
                                    std::to_string(nbp) + " rest positions");
    target = current;
    const std::size_t nbc = clusters_.size();
    std::vector<Vec3> centre(nbc);
    std::vector<Mat3> transform(nbc);
    for (unsigned iter = 0; iter < params_.iterations; ++iter) {
        for (std::size_t i = 0; i < nbc; ++i) {
            // T = Σw p x0ᵀ − (Σw p) Xcm0ᵀ = Σw (p − Xcm)(x0 − Xcm0)ᵀ
            Vec3 sum = Vec3::Zero();
            Mat3 t = Mat3::Zero();
            for (PointId id : clusters_[i]) {
                const auto k = static_cast<std::size_t>(id);
                const bool mechanical = k < nbp;
                const Vec3& p0 = mechanical ? rest_[k] : fixed_rest_[k - nbp];
                const Vec3& p = mechanical ? target[k] : fixed_[k - nbp];
                const double w = mechanical ? 1.0 : params_.fixed_weight;
                sum += p * w;
                t += (p * p0.transpose()) * w;
            }
            t -= sum * rest_centres_[i].transpose();
            centre[i] = sum / weights_[i];
            const double ratio = params_.affine_ratio;
            Mat3 r = Mat3::Zero();
            if (ratio != 1.0) r = sofa_polar_rotation(t);
            transform[i] = ratio != 0.0 ? Mat3((t * inverse_covariance_[i]) * ratio + r * (1.0 - ratio)) : r;
        }
        std::fill(target.begin(), target.end(), Vec3::Zero());
        for (std::size_t i = 0; i < nbc; ++i)
            for (PointId id : clusters_[i]) {
                const auto k = static_cast<std::size_t>(id);
                if (k >= nbp) continue;
                const Vec3 d = rest_[k] - rest_centres_[i];
                const Mat3& m = transform[i];
                const Vec3 moved{m(0, 0) * d[0] + m(0, 1) * d[1] + m(0, 2) * d[2],
                                 m(1, 0) * d[0] + m(1, 1) * d[1] + m(1, 2) * d[2],
                                 m(2, 0) * d[0] + m(2, 1) * d[1] + m(2, 2) * d[2]};
                target[k] += centre[i] + moved;
            }
        for (std::size_t k = 0; k < nbp; ++k) {
            if (clusters_of_point_[k] != 0) target[k] /= static_cast<double>(clusters_of_point_[k]);
            else target[k] = current[k];
        }
    }
}

PositionBasedDynamicsConstraint::PositionBasedDynamicsConstraint(Vec3Object& state, TargetPositions targets,
                                                                 double stiffness, ContextClock dt)
    : state_(&state), targets_(std::move(targets)), stiffness_(stiffness), dt_(std::move(dt)) {}

void PositionBasedDynamicsConstraint::project_position() {
    if (!targets_) return;  // no target positions (SOFA: a size error, nothing done)
    std::vector<Vec3>& x = state_->position;
    targets_(x, target_);
    if (target_.size() != x.size())
        throw std::invalid_argument("PositionBasedDynamicsProjectiveConstraint: " + std::to_string(target_.size()) +
                                    " target positions for a state of " + std::to_string(x.size()) + " points");
    const double dt = dt_();
    if (dt == 0) return;
    const double inv_dt = 1. / dt;
    velocity_.resize(x.size());
    if (old_position_.size() != x.size()) old_position_ = x;
    for (std::size_t i = 0; i < x.size(); ++i) {
        x[i] += (target_[i] - x[i]) * stiffness_;
        velocity_[i] = (x[i] - old_position_[i]) * inv_dt;
        old_position_[i] = x[i];
    }
}

void PositionBasedDynamicsConstraint::project_velocity() {
    // SOFA: an error and nothing done while the velocities are not the state's size
    if (velocity_.size() != state_->velocity.size()) return;
    std::copy(velocity_.begin(), velocity_.end(), state_->velocity.begin());
}

}  // namespace penalty
