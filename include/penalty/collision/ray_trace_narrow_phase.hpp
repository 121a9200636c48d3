#pragma once
/// @file
/// SOFA's RayTraceNarrowPhase over TriangleOctreeCollisionModel surfaces (docs/components/
/// ray_trace_narrow_phase.md): each vertex of a surface A inside surface B's box casts a ray along
/// minus its vertex normal; the first triangle of B the ray meets (found by SOFA's octree walk,
/// TriangleOctree) is a contact when it faces A's triangle and lies closer than A's own far side.

#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/collision/models.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace penalty {

/// One ray hit: triangle `triangle` at origin + t·direction, at barycentric (1 − u − v, u, v)
/// of its vertices 0, 1, 2. triangle = -1: no hit.
struct RayHit {
    int triangle = -1;
    double t = 0.0;
    double u = 0.0;
    double v = 0.0;
};

/// SOFA's sofa::geometry::Triangle::rayIntersection (Möller–Trumbore, tolerance ε = machine
/// epsilon on u, v, u + v and det, and t ≥ ε), operation by operation. Writes t, u, v on success.
[[nodiscard]] bool ray_triangle_hit(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& origin,
                                    const Vec3& direction, double& t, double& u, double& v);

/// SOFA's helper::TriangleOctree over the cube [-800, 800]³: each triangle is stored in every
/// cell of edge 1600 / 2^d (d the largest with 1600 / 2^d ≥ the triangle box's largest extent)
/// that its box's grid points fall in (TriangleOctreeRoot::fillOctree); a triangle outside the
/// cube is not stored. trace() walks the cells along the ray in order (the parametric octree
/// traversal of Revelles et al. 2000, as TriangleOctree::trace) and returns the nearest hit
/// among the triangles of the first leaf with one and of that leaf's ancestors: not always the
/// nearest hit overall (a triangle of an earlier cell may be met beyond a later cell's).
class TriangleOctree {
public:
    static constexpr double kHalfSize = 800.0;  ///< TriangleOctreeRoot::CUBE_SIZE

    /// Builds the tree of `triangles` at `positions` (both read again by trace: keep them alive
    /// and unchanged).
    void build(std::span<const Vec3> positions, std::span<const Triangle> triangles);
    [[nodiscard]] bool built() const { return used_ > 0; }
    void clear() { used_ = 0; }

    /// TriangleOctree::trace(origin, direction, result).
    [[nodiscard]] RayHit trace(const Vec3& origin, const Vec3& direction) const;
    /// Every triangle of the tree the ray hits, by brute force: the nearest (least t, the first
    /// triangle on ties). The reference of the tests.
    [[nodiscard]] RayHit nearest_hit(const Vec3& origin, const Vec3& direction) const;

    [[nodiscard]] std::size_t node_count() const { return used_; }

private:
    struct Node {
        double x = 0.0, y = 0.0, z = 0.0, size = 0.0;  ///< min corner and edge (m)
        std::array<int, 8> children{-1, -1, -1, -1, -1, -1, -1, -1};
        bool leaf = true;
        std::vector<int> triangles;
    };
    struct Ray;  // the walk's fixed data (triangle_octree.cpp)
    [[nodiscard]] int new_node(double x, double y, double z, double size);
    void insert(int node, double x, double y, double z, double cell, int triangle);
    void fill(int triangle);
    [[nodiscard]] int walk(int node, const Ray& ray, double tx0, double ty0, double tz0, double tx1, double ty1,
                           double tz1, RayHit& hit) const;
    [[nodiscard]] int nearest_in(int node, int first, const Ray& ray, RayHit& hit) const;

    std::span<const Vec3> positions_;
    std::span<const Triangle> triangles_;
    std::vector<Node> nodes_;  ///< the first used_ are the tree (the others kept for the next build)
    std::size_t used_ = 0;
};

/// The data SOFA's TriangleOctreeCollisionModel keeps besides its triangles: its own triangle
/// normals, the vertex normals, its box and its octree (TriangleOctreeCollisionModel::
/// computeBoundingTree, buildOctree).
struct OctreeSurface {
    TriangleModel* model = nullptr;
    std::vector<Triangle> triangles;   ///< the model's, for the octree
    std::vector<Vec3> normals;         ///< SOFA's m_normals: triangle 0's from init, the others' from the last update
    std::vector<Vec3> vertex_normals;  ///< pNorms
    Aabb box;                          ///< point 0 and triangles 1 … n−1's vertices, no margin
    bool computed = false;             ///< a non-moving model computes all this once
    TriangleOctree octree;
};

/// SOFA's RayTraceNarrowPhase (RayTraceNarrowPhase::addCollisionPair, findPairsVolume): for each
/// model pair the broad phase passes (root boxes within the alarm distance) whose two models are
/// octree surfaces, the outputs of (A, B) then those of (B, A), each its own detection entry.
/// Output of a vertex P of A's triangle j (the triangle that owns P, flag P1/P2/P3, k its rank
/// among the owned vertices): elements (j, triangle of B hit), points P and the hit point Q,
/// normal = P's vertex normal, value = −t (t = |PQ|), id = 3·j + k.
class RayTraceNarrowPhase final : public NarrowPhaseOverride {
public:
    /// Registers a TriangleOctreeCollisionModel's triangle model; its normals are computed now,
    /// at the current positions (SOFA's TriangleCollisionModel::init, updateNormals).
    void add_surface(TriangleModel& model);
    [[nodiscard]] bool is_surface(const CollisionModel& model) const { return find(model) != nullptr; }

    const SceneDetection& detect(const SceneDetection& broad_pairs) override;
    [[nodiscard]] const SceneDetection& detections() const override { return result_; }

    /// The outputs of findPairsVolume(a, b) at the surfaces' current data (appended).
    void find_pairs(OctreeSurface& a, OctreeSurface& b, DetectionOutputList& out);
    /// TriangleOctreeCollisionModel::computeBoundingTree: the vertex normals from the stored
    /// normals, then the stored normals of triangles 1 … n−1 and the box (once for a model that
    /// does not move); the octree is dropped (built again when a pair needs it).
    static void update_surface(OctreeSurface& s);
    [[nodiscard]] OctreeSurface* find(const CollisionModel& model);
    [[nodiscard]] const OctreeSurface* find(const CollisionModel& model) const;

private:
    std::vector<std::unique_ptr<OctreeSurface>> surfaces_;
    SceneDetection result_;
};

}  // namespace penalty
