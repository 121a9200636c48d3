// Spring force fields whose springs SOFA builds from a surface topology, and SpringForceField
// with explicit spring lists: QuadularBendingSprings, TriangleBendingSprings, QuadBendingSprings,
// SpringForceField. All evaluate the SpringForceField law (penalty::SpringForceField); the spring
// lists are built by include/penalty/mechanics/bending_spring_lists.hpp at init, from the state
// once initialised (SOFA's init order). Also the triangle membranes of the same SOFA examples:
// TriangularTensorMassForceField, TriangularBiquadraticSpringsForceField,
// TriangularQuadraticSpringsForceField.
#include "penalty/mechanics/bending_springs.hpp"
#include "penalty/mechanics/bending_spring_lists.hpp"
#include "penalty/mechanics/rigid_spring_force_field.hpp"
#include "penalty/mechanics/triangular_biquadratic_springs.hpp"
#include "penalty/mechanics/triangular_quadratic_springs.hpp"
#include "penalty/mechanics/triangular_tensor_mass.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

/// A number list attribute, or its spec's default (the registry holds SOFA's default once).
std::vector<double> numbers_or_default(const Attributes& a, std::string_view name) {
    if (a.has(name)) return a.numbers(name);
    const ComponentSpec* spec = find_component(a.component().type);
    const AttributeSpec* attribute = spec != nullptr ? find_attribute(*spec, name) : nullptr;
    std::vector<double> values;
    if (attribute == nullptr) return values;
    std::istringstream in{std::string(attribute->default_value)};
    for (double v = 0; in >> v;) values.push_back(v);
    return values;
}

/// The first value of a SpringForceField `stiffness` / `damping` list (SOFA's ks[0], kd[0];
/// SpringForceField's defaults, 100 N/m and 5 N·s/m, when absent).
double first_of(const Attributes& a, std::string_view name) {
    const std::vector<double> values = numbers_or_default(a, name);
    if (values.empty()) a.fail(name, "is empty");
    if (!std::isfinite(values[0]) || values[0] < 0) a.fail(name, "must be finite and >= 0");
    return values[0];
}

/// A SpringForceField inside the node's state whose springs come from `make_springs(state)` at init.
template <class MakeSprings>
SpringForceField& add_topology_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info, Vec3Object& s,
                                       MakeSprings make_springs) {
    auto* ff = &info.node->add_force_field<SpringForceField>(s);
    b.record_origin(ff, c);
    b.add_init(1, c, [ff, &s, make_springs] {
        for (const Spring& spring : make_springs(s)) ff->add_spring(spring);
        ff->init();
    });
    return *ff;
}

// ---- QuadularBendingSprings -----------------------------------------------------------------
// Defaults: QuadularBendingSprings (stiffness 100000, damping 1).
constexpr AttributeSpec kQuadularBendingSprings[] = {
    {"stiffness", K::real, "100000", "N/m", ValueCheck::nonnegative, "every spring's ks"},
    {"damping", K::real, "1", "N s/m", ValueCheck::nonnegative, "every spring's kd (explicit only)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its quads and edges"},
};

void build_quadular_bending_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const double ks = a.real("stiffness");
        const double kd = a.real("damping");
        const MeshTopology& topology = b.topology_of(a, info);
        // springs from the rest positions (QuadularBendingSprings::applyQuadCreation)
        SpringForceField& ff = add_topology_springs(b, c, info, s, [&topology, ks, kd](const Vec3Object& state) {
            return quadular_bending_springs(topology, state.rest_position, ks, kd);
        });
        ff.set_null_length(kBendingSpringNullLength);  // QuadularBendingSprings::computeSpringForce
        ff.set_arithmetic(SpringArithmetic::quadular_bending_springs);
        ff.set_sofa_interaction(false);  // SOFA's QuadularBendingSprings is a ForceField, not a SpringForceField
        b.role(c, [f = &ff] {
            return counted(f->springs().size(), "bending spring", "bending springs") +
                   " (two across each edge shared by two quads)";
        });
    });
    b.note_unread_attributes(c);
}

// ---- TriangleBendingSprings, QuadBendingSprings ---------------------------------------------
// SpringForceField subclasses: stiffness and damping are SpringForceField's lists (defaults
// 100 N/m and 5 N·s/m, SpringForceField.h defaultSpringStiffness / defaultSpringDamping), of
// which the first value applies to every spring.
constexpr AttributeSpec kTriangleBendingSprings[] = {
    {"stiffness", K::numbers, "100", "N/m", ValueCheck::none, "the first value: every spring's ks"},
    {"damping", K::numbers, "5", "N s/m", ValueCheck::none, "the first value: every spring's kd (explicit only)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles and quads"},
};

void build_triangle_bending_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const double ks = first_of(a, "stiffness");
        const double kd = first_of(a, "damping");
        const MeshTopology& topology = b.topology_of(a, info);
        // springs from the positions at init (TriangleBendingSprings::addSpring)
        SpringForceField& ff = add_topology_springs(b, c, info, s, [&topology, ks, kd](const Vec3Object& state) {
            return triangle_bending_springs(topology, state.position, ks, kd);
        });
        b.role(c, [f = &ff] {
            return counted(f->springs().size(), "bending spring", "bending springs") +
                   " between the opposite vertices of faces sharing an edge";
        });
    });
    b.note_unread_attributes(c);
}

constexpr AttributeSpec kQuadBendingSprings[] = {
    {"stiffness", K::numbers, "100", "N/m", ValueCheck::none, "the first value: every spring's ks"},
    {"damping", K::numbers, "5", "N s/m", ValueCheck::none, "the first value: every spring's kd (explicit only)"},
    {"localRange", K::numbers, "-1 -1", "", ValueCheck::none,
     "skip springs with both ends below / above (-1: no bound)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its quads"},
};

void build_quad_bending_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const double ks = first_of(a, "stiffness");
        const double kd = first_of(a, "damping");
        const std::vector<double> range_values = numbers_or_default(a, "localRange");
        if (range_values.size() != 2) a.fail("localRange", "needs two integers");
        const std::vector<int> ends = a.as_ints("localRange", range_values);
        const LocalRange range{ends[0], ends[1]};
        const MeshTopology& topology = b.topology_of(a, info);
        // springs from the positions at init (QuadBendingSprings::addSpring)
        SpringForceField& ff = add_topology_springs(b, c, info, s, [&topology, ks, kd, range](const Vec3Object& state) {
            return quad_bending_springs(topology, state.position, ks, kd, range);
        });
        b.role(c, [f = &ff] {
            return counted(f->springs().size(), "bending spring", "bending springs") +
                   " across the edges shared by two quads";
        });
    });
    b.note_unread_attributes(c);
}

// ---- SpringForceField -------------------------------------------------------------------------
// SpringForceField::init: the `spring` list (m1 m2 ks kd L per spring, LinearSpring's operator>>)
// when given, else one spring per entry of indices1/indices2 with the lists lengths (default 0),
// stiffness and damping resized to it by repeating their last value
// (SpringForceField::updateSpringsFromTopologyIndices).
constexpr AttributeSpec kSpringForceField[] = {
    {"spring", K::numbers, "", "", ValueCheck::none, "m1 m2 ks kd L per spring (N/m, N s/m, m)"},
    {"indices1", K::indices, "", "", ValueCheck::none, "first end of each spring (without spring)"},
    {"indices2", K::indices, "", "", ValueCheck::none, "second end of each spring (without spring)"},
    {"lengths", K::numbers, "0", "m", ValueCheck::none, "rest lengths (without spring; last value repeated)"},
    {"length", K::numbers, "0", "m", ValueCheck::none, "alias of lengths"},
    {"stiffness", K::numbers, "100", "N/m", ValueCheck::none, "ks per spring (without spring; last value repeated)"},
    {"damping", K::numbers, "5", "N s/m", ValueCheck::none, "kd per spring (without spring; last value repeated)"},
    {"elongationOnly", K::text, "0", "", ValueCheck::none, "only false is supported"},
    {"enabled", K::text, "1", "", ValueCheck::none, "only true is supported"},
    {"object1", K::link, "(the node's state)", "", ValueCheck::none, "state of each spring's first end"},
    {"object2", K::link, "(the node's state)", "", ValueCheck::none, "state of each spring's second end"},
};

/// `list` resized to `n` entries by repeating its last value (SOFA's resize(n, back())).
std::vector<double> resized(std::vector<double> list, std::size_t n, std::string_view name, const Attributes& a) {
    if (list.empty()) a.fail(name, "is empty");
    list.resize(n, list.back());
    return list;
}

/// Checks that a boolean list holds only `expected` (penalty's springs have no flags).
void require_all(const Attributes& a, std::string_view name, bool expected) {
    if (!a.has(name)) return;
    const std::string text = a.text(name);
    std::size_t start = 0;
    while (start < text.size()) {
        const std::size_t space = text.find_first_of(" \t\r\n", start);
        const std::string word = text.substr(start, space == std::string::npos ? std::string::npos : space - start);
        if (!word.empty()) {
            const bool is_true = word == "1" || word == "true";
            const bool is_false = word == "0" || word == "false";
            if (!is_true && !is_false) a.fail(name, "'" + word + "' is not a boolean");
            if (is_true != expected)
                a.fail(name, std::string("only ") + (expected ? "true" : "false") + " is supported");
        }
        if (space == std::string::npos) break;
        start = space + 1;
    }
}

std::vector<Spring> explicit_springs(const Attributes& a) {
    std::vector<Spring> springs;
    if (a.has("spring")) {
        const std::vector<double> v = a.numbers("spring");
        if (v.size() % 5 != 0) a.fail("spring", "needs 5 numbers per spring (m1 m2 ks kd L)");
        for (std::size_t i = 0; i < v.size(); i += 5) {
            // as indices1/indices2 (io::get_indices): integers from 0 to PointId's largest
            for (std::size_t j = 0; j < 2; ++j)
                if (!(v[i + j] >= 0) || v[i + j] != std::floor(v[i + j]) ||
                    v[i + j] > double(std::numeric_limits<PointId>::max()))
                    a.fail("spring",
                           "indices must be integers from 0 to " + std::to_string(std::numeric_limits<PointId>::max()));
            springs.push_back({.a = static_cast<Index>(v[i]),
                               .b = static_cast<Index>(v[i + 1]),
                               .ks = v[i + 2],
                               .kd = v[i + 3],
                               .rest_length = v[i + 4]});
        }
        return springs;
    }
    const std::vector<PointId> first = a.indices("indices1");
    const std::vector<PointId> second = a.indices("indices2");
    if (first.size() != second.size()) a.fail("indices2", "must have as many entries as indices1");
    if (first.empty()) return springs;
    const std::string_view lengths_name = a.has("lengths") || !a.has("length") ? "lengths" : "length";
    const std::vector<double> lengths = resized(numbers_or_default(a, lengths_name), first.size(), lengths_name, a);
    const std::vector<double> ks = resized(numbers_or_default(a, "stiffness"), first.size(), "stiffness", a);
    const std::vector<double> kd = resized(numbers_or_default(a, "damping"), first.size(), "damping", a);
    for (std::size_t i = 0; i < first.size(); ++i)
        springs.push_back({.a = first[i], .b = second[i], .ks = ks[i], .kd = kd[i], .rest_length = lengths[i]});
    return springs;
}

void build_spring_force_field(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    std::vector<Spring> springs;
    b.guarded(c, [&] {
        require_all(a, "elongationOnly", false);
        require_all(a, "enabled", true);
        springs = explicit_springs(a);
    });
    // object1 / object2: the states the springs join (default: the node's state); a state of a node
    // below this one is built later, so the field is then added once every node is built
    const auto create = [&b, &c, &info, springs] {
        const Attributes attributes(c);
        const auto end_state = [&](std::string_view end) -> BaseState& {
            if (!attributes.has(end)) return b.state(c, info);
            BaseState* s = b.linked_state(attributes, end);
            if (s == nullptr) attributes.fail(end, "links to a state that is not built");
            return *s;
        };
        BaseState& e1 = end_state("object1");
        BaseState& e2 = end_state("object2");
        auto* r1 = dynamic_cast<Rigid3Object*>(&e1);
        auto* r2 = dynamic_cast<Rigid3Object*>(&e2);
        if ((r1 == nullptr) != (r2 == nullptr))
            attributes.fail(r1 == nullptr ? "object2" : "object1",
                            "links to a Rigid3d state and the other end to a Vec3d one");
        if (r1 != nullptr) {  // SpringForceField<Rigid3>: springs between the frames' centres
            auto* rf = &info.node->add_force_field<RigidSpringForceField>(*r1, *r2, springs);
            b.record_origin(rf, c);
            b.add_init(1, c, [rf] { rf->init(); });
            b.role(c, [rf] {
                return counted(rf->springs().size(), "spring", "springs") + " between Rigid3d frame centres";
            });
            return;
        }
        Vec3Object& s1 = dynamic_cast<Vec3Object&>(e1);
        Vec3Object& s2 = dynamic_cast<Vec3Object&>(e2);
        auto* ff = &info.node->add_force_field<SpringForceField>(s1, s2);
        for (const Spring& spring : springs) ff->add_spring(spring);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, two = &s1 != &s2] {
            return counted(ff->springs().size(), "spring", "springs") + " (explicit list" +
                   (two ? std::string(", between two states)") : std::string(")"));
        });
    };
    b.build_when_ends_exist(c, a, create);
    b.note_unread_attributes(c);
}

// ---- TriangularTensorMassForceField ---------------------------------------------------------
// Defaults: TriangularTensorMassForceField (youngModulus 1000, poissonRatio 0.3).
constexpr AttributeSpec kTriangularTensorMass[] = {
    {"youngModulus", K::real, "1000", "Pa", ValueCheck::nonnegative, "E (membrane, unit thickness)"},
    {"poissonRatio", K::real, "0.3", "", ValueCheck::none, "nu, not +-1"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles and edges"},
};

void build_triangular_tensor_mass(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        TensorMassParameters p;
        p.young_modulus = a.real("youngModulus");
        p.poisson_ratio = a.real("poissonRatio");
        auto* ff = &info.node->add_force_field<TriangularTensorMassForceField>(s, b.topology_of(a, info), p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, p] {
            return counted(ff->edge_tensors().size(), "edge tensor", "edge tensors") + ", E = " + num(p.young_modulus) +
                   " Pa, nu = " + num(p.poisson_ratio) + " (linear, from the rest positions)";
        });
    });
    b.note_unread_attributes(c);
}

// ---- TriangularBiquadraticSpringsForceField -------------------------------------------------
// Defaults: TriangularBiquadraticSpringsForceField's constructor.
constexpr AttributeSpec kTriangularBiquadraticSprings[] = {
    {"youngModulus", K::real, "1000", "Pa", ValueCheck::nonnegative, "E (membrane, unit thickness)"},
    {"poissonRatio", K::real, "0.3", "", ValueCheck::none, "nu, not +-1"},
    {"dampingRatio", K::real, "0", "s", ValueCheck::none, "damping / stiffness of the edge springs (explicit)"},
    {"useAngularSprings", K::boolean, "1", "", ValueCheck::none, "couple the edges of each triangle"},
    {"compressible", K::boolean, "1", "", ValueCheck::none, "area term of compressed triangles (with angular springs)"},
    {"matrixRegularization", K::real, "0.4", "", ValueCheck::none, "no effect (SOFA never reads it)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles and edges"},
};

void build_triangular_biquadratic_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        BiquadraticSpringParameters p;
        p.young_modulus = a.real("youngModulus");
        p.poisson_ratio = a.real("poissonRatio");
        p.damping_ratio = a.real("dampingRatio");
        p.use_angular_springs = a.boolean("useAngularSprings");
        p.compressible = a.boolean("compressible");
        static_cast<void>(a.real("matrixRegularization"));  // SOFA declares it and never reads it
        auto* ff = &info.node->add_force_field<TriangularBiquadraticSpringsForceField>(s, b.topology_of(a, info), p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, p] {
            return counted(ff->edge_stiffness().size(), "edge spring", "edge springs") +
                   " on squared lengths, E = " + num(p.young_modulus) + " Pa, nu = " + num(p.poisson_ratio) +
                   (p.use_angular_springs ? ", angular springs" : "") +
                   (p.use_angular_springs && p.compressible ? ", area term under compression" : "");
        });
    });
    b.note_unread_attributes(c);
}

// ---- TriangularQuadraticSpringsForceField ---------------------------------------------------
// Defaults: TriangularQuadraticSpringsForceField's constructor.
constexpr AttributeSpec kTriangularQuadraticSprings[] = {
    {"youngModulus", K::real, "1000", "Pa", ValueCheck::nonnegative, "E (membrane, unit thickness)"},
    {"poissonRatio", K::real, "0.3", "", ValueCheck::none, "nu, not +-1"},
    {"dampingRatio", K::real, "0", "s", ValueCheck::none, "damping / stiffness of the edge springs (explicit)"},
    {"useAngularSprings", K::boolean, "1", "", ValueCheck::none, "couple the edges of each triangle"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles and edges"},
};

void build_triangular_quadratic_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        QuadraticSpringParameters p;
        p.young_modulus = a.real("youngModulus");
        p.poisson_ratio = a.real("poissonRatio");
        p.damping_ratio = a.real("dampingRatio");
        p.use_angular_springs = a.boolean("useAngularSprings");
        auto* ff = &info.node->add_force_field<TriangularQuadraticSpringsForceField>(s, b.topology_of(a, info), p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, p] {
            return counted(ff->edge_stiffness().size(), "edge spring", "edge springs") +
                   " on lengths, E = " + num(p.young_modulus) + " Pa, nu = " + num(p.poisson_ratio) +
                   (p.use_angular_springs ? ", angular springs" : "");
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kBendingSpringComponents[] = {
    {.type = "QuadularBendingSprings",
     .family = F::force_field,
     .summary = "two springs across each edge shared by two quads",
     .attributes = kQuadularBendingSprings,
     .build = build_quadular_bending_springs},
    {.type = "TriangleBendingSprings",
     .family = F::force_field,
     .summary = "springs between the opposite vertices of faces sharing an edge",
     .attributes = kTriangleBendingSprings,
     .build = build_triangle_bending_springs},
    {.type = "QuadBendingSprings",
     .family = F::force_field,
     .summary = "springs across the edges shared by two quads",
     .attributes = kQuadBendingSprings,
     .build = build_quad_bending_springs},
    {.type = "SpringForceField",
     .family = F::force_field,
     .summary = "springs of an explicit list",
     .attributes = kSpringForceField,
     .build = build_spring_force_field},
    {.type = "TriangularTensorMassForceField",
     .family = F::force_field,
     .summary = "linear triangle membrane as per-edge tensors",
     .attributes = kTriangularTensorMass,
     .build = build_triangular_tensor_mass},
    {.type = "TriangularBiquadraticSpringsForceField",
     .family = F::force_field,
     .summary = "springs on squared edge lengths of triangles, coupled per triangle",
     .attributes = kTriangularBiquadraticSprings,
     .build = build_triangular_biquadratic_springs},
    {.type = "TriangularQuadraticSpringsForceField",
     .family = F::force_field,
     .summary = "springs on edge lengths of triangles, coupled per triangle",
     .attributes = kTriangularQuadraticSprings,
     .build = build_triangular_quadratic_springs},
};

}  // namespace

std::span<const ComponentSpec> bending_spring_components() { return kBendingSpringComponents; }

}  // namespace penalty::scene::builder
