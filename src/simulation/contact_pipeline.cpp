#include "penalty/simulation/contact_pipeline.hpp"

#include "penalty/collision/models.hpp"

#include <algorithm>
#include <string>

namespace penalty {

// ---- ContactPointMapping ----------------------------------------------------------------------
namespace {
template <class Deriv>
std::span<const double> flat_of(std::span<const Deriv> v) {
    return {reinterpret_cast<const double*>(v.data()), v.size() * (sizeof(Deriv) / sizeof(double))};
}
template <class Deriv>
std::span<double> flat_of(std::span<Deriv> v) {
    return {reinterpret_cast<double*>(v.data()), v.size() * (sizeof(Deriv) / sizeof(double))};
}
}  // namespace

template <class In>
void ContactPointMapping<In>::init() {
    Vec3Object& out = *this->out_;
    const std::size_t n = mapper_->size();
    out.position.assign(n, Vec3::Zero());
    out.velocity.assign(n, Vec3::Zero());
    out.force.assign(n, Vec3::Zero());
    out.external_force.assign(n, Vec3::Zero());
    out.dx.assign(n, Vec3::Zero());
    out.df.assign(n, Vec3::Zero());
    this->apply_position();
    out.rest_position = out.position;
    this->apply_velocity();
}

template <class In>
void ContactPointMapping<In>::apply(std::span<Vec3> out, std::span<const InCoord> /*in*/) {
    // The mapper reads the same state (checked by the pipeline) and freezes its weights.
    mapper_->update();
    const ConstVec3Span p = mapper_->positions();
    PENALTY_DEMAND(p.size() == out.size());
    std::copy(p.begin(), p.end(), out.begin());
}

template <class In>
void ContactPointMapping<In>::apply_j(std::span<Vec3> out, std::span<const InDeriv> in) const {
    mapper_->apply_j(flat_of(in), out);
}

template <class In>
void ContactPointMapping<In>::apply_jt(std::span<InDeriv> in, std::span<const Vec3> out) const {
    mapper_->apply_jt(out, flat_of(in));
}

template class ContactPointMapping<Vec3Types>;
template class ContactPointMapping<Rigid3Types>;

// ---- ContactPipeline --------------------------------------------------------------------------
namespace {
/// The state a collision model reads (as its MechanicalState base), and whether it is Rigid3.
std::pair<const void*, bool> model_state(const CollisionModel& m) {
    if (const auto* p = dynamic_cast<const PointModel*>(&m)) return {&p->state(), false};
    if (const auto* p = dynamic_cast<const LineModel*>(&m)) return {&p->state(), false};
    if (const auto* p = dynamic_cast<const TriangleModel*>(&m)) return {&p->state(), false};
    if (const auto* p = dynamic_cast<const SphereModel*>(&m)) return {&p->state(), false};
    if (const auto* p = dynamic_cast<const TetrahedronModel*>(&m)) return {&p->state(), false};
    if (const auto* p = dynamic_cast<const RigidSphereModel*>(&m)) return {&p->state(), true};
    if (const auto* p = dynamic_cast<const CylinderModel*>(&m)) return {&p->state(), true};
    throw_invalid_argument("ContactPipeline::add_model: model '", m.name(), "' has an unknown model class");
}

/// Ids given to nodes for the same-node rule, far from ids users typically choose.
constexpr int kNodeIdBase = 1 << 24;
}  // namespace

ContactPipeline::ContactPipeline(Simulation& simulation, const IntersectionParams& intersection,
                                 CollisionResponse response, Node* node)
    : simulation_(&simulation), intersection_(intersection), response_(std::move(response)),
      node_(node ? node : &simulation.root()) {
    intersection_.validate();
    if (simulation.collision_hook)
        throw_invalid_argument("ContactPipeline: the simulation already has a collision_hook");
    response_.on_create = [this](BarycentricPenaltyContact& c) { on_create(c); };
    response_.on_destroy = [this](BarycentricPenaltyContact& c) { on_destroy(c); };
    simulation.collision_hook = [this](Simulation&) { update(); };
}

ContactPipeline::~ContactPipeline() {
    simulation_->collision_hook = nullptr;
    response_.clear();  // on_destroy removes every graph entry
    response_.on_create = nullptr;
    response_.on_destroy = nullptr;
}

void ContactPipeline::add_model(CollisionModel& model, Node& node) {
    for (const auto& e : models_)
        if (e.model == &model) throw_invalid_argument("ContactPipeline::add_model: model '", model.name(), "' is already registered");
    const auto [state, rigid] = model_state(model);
    ModelEntry e{&model, &node, nullptr, nullptr};
    if (rigid) {
        e.rigid = dynamic_cast<Rigid3Object*>(node.state());
        if (!e.rigid || static_cast<const Rigid3State*>(e.rigid) != state)
            throw_invalid_argument("ContactPipeline::add_model: model '", model.name(), "' (", model_type_name(model.type()),
                                   ") reads a Rigid3 state that is not the state of node '", node.name(), "'");
    } else {
        e.vec3 = dynamic_cast<Vec3Object*>(node.state());
        if (!e.vec3 || static_cast<const Vec3State*>(e.vec3) != state)
            throw_invalid_argument("ContactPipeline::add_model: model '", model.name(), "' (", model_type_name(model.type()),
                                   ") reads a Vec3 state that is not the state of node '", node.name(), "'");
    }
    if (model.params().node == -1) {
        auto it = std::find(node_ids_.begin(), node_ids_.end(), &node);
        if (it == node_ids_.end()) {
            node_ids_.push_back(&node);
            it = node_ids_.end() - 1;
        }
        model.params().node = kNodeIdBase + static_cast<int>(it - node_ids_.begin());
    }
    models_.push_back(e);
}

const ContactPipeline::ModelEntry& ContactPipeline::model_entry(const CollisionModel& m) const {
    for (const auto& e : models_)
        if (e.model == &m) return e;
    throw_invalid_argument("ContactPipeline: model '", m.name(), "' is not registered");
}

void ContactPipeline::update() {
    detections_.clear();
    for (std::size_t i = 0; i < models_.size(); ++i) {
        for (std::size_t j = i; j < models_.size(); ++j) {
            CollisionModel& a = *models_[i].model;
            CollisionModel& b = *models_[j].model;
            if (!keep_model_pair(a, b)) continue;
            const PairSupport s = pair_support(intersection_, a.type(), b.type());
            if (s != PairSupport::Supported && !(s == PairSupport::BeyondSofa && intersection_.enable_beyond_sofa_pairs)) {
                const std::pair<const CollisionModel*, const CollisionModel*> key{&a, &b};
                if (std::find(skipped_keys_.begin(), skipped_keys_.end(), key) == skipped_keys_.end()) {
                    skipped_keys_.push_back(key);
                    skipped_pairs_.push_back(detail::concat(
                        "ContactPipeline: models '", a.name(), "' (", model_type_name(a.type()), ") and '",
                        b.name(), "' (", model_type_name(b.type()), "): pair ", pair_support_name(s),
                        " for this intersection method, no contact"));
                }
                continue;
            }
            detections_.push_back(detect_model_pair(intersection_, a, b));
        }
    }
    response_.set_detections(detections_, intersection_.contact_distance);
    // The springs and contact points are rebuilt: size the mapped contact states to them.
    for (auto& e : entries_)
        for (BaseMapping* m : e.mappings)
            if (m) m->init();
}

const ContactGraphEntry* ContactPipeline::find(const CollisionModel& m1, const CollisionModel& m2) const {
    for (const auto& e : entries_)
        if (&e.contact->model1() == &m1 && &e.contact->model2() == &m2) return &e;
    return nullptr;
}

void ContactPipeline::on_create(BarycentricPenaltyContact& contact) {
    const ModelEntry& me1 = model_entry(contact.model1());
    const ModelEntry& me2 = model_entry(contact.model2());
    ContactGraphEntry e;
    e.contact = &contact;
    const std::size_t id = created_count_++;
    const std::array<const ModelEntry*, 2> sides = {&me1, &me2};
    for (int s = 0; s < 2; ++s) {
        const ModelEntry& me = *sides[std::size_t(s)];
        ContactMapper& mapper = s == 0 ? contact.mapper1() : contact.mapper2();
        if (mapper.kind() == ContactMapperKind::identity) {
            if (!me.vec3) throw_invalid_argument("ContactPipeline: identity contact mapper on non-Vec3 model '", me.model->name(), "'");
            e.point_states[std::size_t(s)] = me.vec3;
            continue;
        }
        const std::string name = "contact" + std::to_string(id) + "_" + contact.model1().name() + "_" +
                                 contact.model2().name() + "_" + std::to_string(s + 1);
        Node& pn = me.node->add_child(name);
        Vec3Object& st = pn.add_state<Vec3Types>(name);
        BaseMapping* map = nullptr;
        if (me.vec3) {
            map = &pn.set_mapping<ContactPointMapping<Vec3Types>>(*me.vec3, st, mapper);
        } else {
            map = &pn.set_mapping<ContactPointMapping<Rigid3Types>>(*me.rigid, st, mapper);
        }
        map->init();
        e.point_nodes[std::size_t(s)] = &pn;
        e.point_states[std::size_t(s)] = &st;
        e.mappings[std::size_t(s)] = map;
    }
    // Spec §2.1 (SubCollisionPipeline::computeCollisionResponse).
    if (!contact.model1().params().simulated) {
        e.host = me2.node;
    } else if (!contact.model2().params().simulated) {
        e.host = me1.node;
    } else {
        e.host = node_;
    }
    auto ff = std::make_unique<ContactInteraction>(*e.point_states[0], *e.point_states[1], contact.force_field());
    e.force_field = ff.get();
    e.host->add_force_field_ptr(std::move(ff));
    entries_.push_back(e);
}

void ContactPipeline::remove_entry(ContactGraphEntry& e) {
    e.host->remove_force_field(e.force_field);
    for (Node* n : e.point_nodes)
        if (n) n->parent()->remove_child(n);
}

void ContactPipeline::on_destroy(BarycentricPenaltyContact& contact) {
    const auto it = std::find_if(entries_.begin(), entries_.end(), [&](const ContactGraphEntry& e) { return e.contact == &contact; });
    if (it == entries_.end()) return;
    remove_entry(*it);
    entries_.erase(it);
}

}  // namespace penalty
