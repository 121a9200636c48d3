#include "penalty/simulation/contact_pipeline.hpp"

#include "penalty/collision/models.hpp"
#include "penalty/core/first_error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <type_traits>

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
    // The mapper's points are current (set_detection_outputs updated them at these parent
    // positions and velocities): copied, not computed again.
    Vec3Object& out = *this->out_;
    const std::size_t n = mapper_->size();
    out.position.assign(mapper_->positions().begin(), mapper_->positions().end());
    out.velocity.assign(mapper_->velocities().begin(), mapper_->velocities().end());
    out.force.assign(n, Vec3::Zero());
    out.external_force.assign(n, Vec3::Zero());
    out.dx.assign(n, Vec3::Zero());
    out.df.assign(n, Vec3::Zero());
    out.rest_position = out.position;
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

template <class In>
bool ContactPointMapping<In>::list_inputs_read(std::vector<std::uint32_t>& rows) const {
    if (mapper_->kind() != ContactMapperKind::barycentric) return false;
    for (const ContactBarycentricRow& row : static_cast<const BarycentricContactMapper&>(*mapper_).rows())
        for (const ContactBarycentricRow::Entry& e : row) {
            PENALTY_DEMAND(e.index >= 0);
            rows.push_back(static_cast<std::uint32_t>(e.index));
        }
    return true;
}

template <class In>
const std::vector<ContactBarycentricRow>* ContactPointMapping<In>::contact_barycentric_rows() const {
    if constexpr (std::is_same_v<In, Vec3Types>) {
        if (mapper_->kind() == ContactMapperKind::barycentric)
            return &static_cast<const BarycentricContactMapper&>(*mapper_).rows();
    }
    return nullptr;
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

}  // namespace

struct ContactPipeline::ThreadArena {
    explicit ThreadArena(int threads) : arena(threads) {}
    tbb::task_arena arena;
};

template <class F>
void ContactPipeline::run_detection(const F& f) {
    if (arena_ == nullptr) {
        f();
        return;
    }
    arena_->arena.execute(f);
}

namespace {
CollisionPipelineOptions collision_options(const ContactPipelineOptions& options) {
    CollisionPipelineOptions bvh = options.bvh;
    bvh.contact_outputs_only = !options.all_detection_outputs;
    return bvh;
}
}  // namespace

ContactPipeline::ContactPipeline(Simulation& simulation, const IntersectionParams& intersection,
                                 CollisionResponse response, Node* node, const ContactPipelineOptions& options)
    : simulation_(&simulation),
      intersection_(intersection),
      response_(std::move(response)),
      node_(node ? node : &simulation.root()),
      options_(options),
      collision_(intersection, collision_options(options), options.detection) {
    if (options_.threads < 0 || options_.threads > kMaxDetectionThreads)
        throw_invalid_argument("ContactPipeline: options.threads must be between 0 and ", kMaxDetectionThreads,
                               ", got ", options_.threads);
    // options.bvh.leaf_size = 0 and bad intersection parameters: thrown by collision_
    if (options_.threads > 0)
        arena_ = std::make_unique<ThreadArena>(options_.threads);  // once: TBB makes its threads lazily
    response_.on_create = [this](BarycentricPenaltyContact& c) { on_create(c); };
    response_.on_destroy = [this](BarycentricPenaltyContact& c) { on_destroy(c); };
    response_.on_destroy_done = [this] { remove_destroyed_entries(); };
    response_.model_rank = [this](const CollisionModel& m) { return model_entry(m).scene_rank; };
    response_.sofa_stable_id_order = options_.sofa_stable_id_order;
    if (options_.register_stage) simulation.add_contact_stage(*this);
}

ContactPipeline::~ContactPipeline() {
    simulation_->remove_contact_stage(*this);
    for (EulerImplicitSolver* s : attached_solvers_) s->newton.update_geometry = nullptr;
    response_.clear();  // on_destroy removes every graph entry
    response_.on_create = nullptr;
    response_.on_destroy = nullptr;
    response_.on_destroy_done = nullptr;
}

void ContactPipeline::add_model(CollisionModel& model, Node& node, std::size_t scene_rank) {
    for (const auto& e : models_)
        if (e.model == &model)
            throw_invalid_argument("ContactPipeline::add_model: model '", model.name(), "' is already registered");
    const auto [state, rigid] = model_state(model);
    ModelEntry e{&model, &node, nullptr, nullptr, scene_rank == kRegistrationOrder ? models_.size() : scene_rank,
                 {},     {},    {},      {}};
    if (rigid) {
        e.rigid = dynamic_cast<Rigid3Object*>(node.state());
        if (!e.rigid || static_cast<const Rigid3State*>(e.rigid) != state)
            throw_invalid_argument("ContactPipeline::add_model: model '", model.name(), "' (",
                                   model_type_name(model.type()),
                                   ") reads a Rigid3 state that is not the state of node '", node.name(), "'");
    } else {
        e.vec3 = dynamic_cast<Vec3Object*>(node.state());
        if (!e.vec3 || static_cast<const Vec3State*>(e.vec3) != state)
            throw_invalid_argument("ContactPipeline::add_model: model '", model.name(), "' (",
                                   model_type_name(model.type()),
                                   ") reads a Vec3 state that is not the state of node '", node.name(), "'");
    }
    if (model.params().node == -1) model.params().node = kAutoNodeIdBase + node.id();
    model_index_.emplace(&model, models_.size());
    models_.push_back(e);
    collision_.add_model(model);
}

std::size_t ContactPipeline::model_index(const CollisionModel& m) const {
    // a hash lookup: a pair's creation looks its two models up (a search was quadratic in the
    // models of a pile of bodies)
    const std::size_t i = model_index_.find(&m);
    if (i == PointerIndex<CollisionModel>::npos)
        throw_invalid_argument("ContactPipeline: model '", m.name(), "' is not registered");
    return i;
}

const ContactPipeline::ModelEntry& ContactPipeline::model_entry(const CollisionModel& m) const {
    return models_[model_index(m)];
}

void ContactPipeline::record_skipped_pairs() {
    for (const ModelPair& p : collision_.unsupported_pairs()) {
        if (std::find(skipped_keys_.begin(), skipped_keys_.end(), p) != skipped_keys_.end()) continue;
        skipped_keys_.push_back(p);
        const CollisionModel& a = *p.model1;
        const CollisionModel& b = *p.model2;
        skipped_pairs_.push_back(detail::concat("ContactPipeline: models '", a.name(), "' (", model_type_name(a.type()),
                                                ") and '", b.name(), "' (", model_type_name(b.type()), "): pair ",
                                                pair_support_name(pair_support(intersection_, a.type(), b.type())),
                                                " for this intersection method, no contact"));
    }
}

void ContactPipeline::update() {
    detect();
    respond();
}

void ContactPipeline::detect() {
    const auto t0 = std::chrono::steady_clock::now();
    run_detection([&] { (void)collision_.detect(); });
    record_skipped_pairs();
    timings_.detection_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void ContactPipeline::respond() {
    const auto t1 = std::chrono::steady_clock::now();
    // Newton iterates rebuild from the state before this update (see the header).
    if (keep_step_start_) {
        for (std::size_t i = 0; i < entries_.size(); ++i) {
            StepStart& st = step_start_[i];
            st.field_before = entries_[i].contact->force_field();
            st.outputs_before = std::move(st.last_outputs);
            st.last_outputs.clear();
        }
    }
    // in the detection's arena: the contacts are fed in parallel there (set_detections)
    run_detection([&] { response_.set_detections(collision_.detections(), intersection_.contact_distance); });
    order_graph_entries();
    if (keep_step_start_) record_fed_outputs();
    if (keep_step_start_) {
        for (ModelEntry& m : models_) {
            if (m.vec3) {
                m.start_x = m.vec3->position;
                m.start_v = m.vec3->velocity;
            } else {
                m.start_rx = m.rigid->position;
                m.start_rv = m.rigid->velocity;
            }
        }
    }
    snapshot_valid_ = keep_step_start_;
    geometry_updates_ = 0;
    init_contact_states();
    timings_.response_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
}

void ContactPipeline::init_contact_states() {
    // The springs and contact points are rebuilt: size the mapped contact states to them. Each
    // entry's mappings write only their own contact states: in parallel (in the detection's
    // arena) when the contacts were fed in parallel, the same bits either way.
    const auto init_entry = [this](std::size_t i) {
        for (BaseMapping* m : entries_[i].mappings)
            if (m) m->init();
    };
    if (!response_.last_feed_concurrent()) {
        for (std::size_t i = 0; i < entries_.size(); ++i) init_entry(i);
        return;
    }
    FirstErrorInOrder failure;
    run_detection([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries_.size(), 16),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i)
                                  if (!failure.run(i, [&] { init_entry(i); })) return;
                          });
    });
    failure.rethrow_if_any();
}

void ContactPipeline::order_graph_entries() {
    // entries_ holds one entry per live contact; the response's pairs are in contact-map order.
    std::size_t k = 0;
    bool in_order = true;
    for (const ContactPairEntry& p : response_.pairs()) {
        if (!p.contact) continue;
        if (k >= entries_.size() || entries_[k].contact != p.contact.get()) in_order = false;
        ++k;
    }
    if (!in_order) {
        // each pair's entry by a hash lookup (a search per pair is quadratic in the live pairs)
        entry_of_scratch_.clear();
        for (std::size_t i = 0; i < entries_.size(); ++i) entry_of_scratch_.emplace(entries_[i].contact, i);
        entries_scratch_.clear();
        step_start_scratch_.clear();
        for (const ContactPairEntry& p : response_.pairs()) {
            if (!p.contact) continue;
            const std::size_t i = entry_of_scratch_.find(p.contact.get());
            PENALTY_DEMAND(i != PointerIndex<BarycentricPenaltyContact>::npos);
            entries_scratch_.push_back(entries_[i]);
            step_start_scratch_.push_back(std::move(step_start_[i]));
        }
        entries_.swap(entries_scratch_);
        step_start_.swap(step_start_scratch_);
    }
    // SubCollisionPipeline::computeCollisionResponse re-adds every contact's force field to its
    // node at each step: a node visits its contact force fields in contact-map order, those of a
    // later sub-pipeline after those of an earlier one (each update() moves its own to the end).
    // The entries grouped by host with a sort of (host, entry index) (a search of the hosts per
    // entry was quadratic): each host's fields in entry order; the hosts' moves are independent.
    host_entries_scratch_.clear();
    for (std::size_t i = 0; i < entries_.size(); ++i) host_entries_scratch_.emplace_back(entries_[i].host, i);
    std::sort(host_entries_scratch_.begin(), host_entries_scratch_.end());
    for (std::size_t g = 0; g < host_entries_scratch_.size();) {
        Node* host = host_entries_scratch_[g].first;
        fields_scratch_.clear();
        for (; g < host_entries_scratch_.size() && host_entries_scratch_[g].first == host; ++g)
            fields_scratch_.push_back(entries_[host_entries_scratch_[g].second].force_field);
        host->move_force_fields_to_end(fields_scratch_);
    }
}

void ContactPipeline::record_fed_outputs() {
    // The outputs each live pair was fed by the last update, its entry found by a hash lookup
    // (a search of the entries per detection was quadratic in the live pairs).
    entry_of_scratch_.clear();
    for (std::size_t i = 0; i < entries_.size(); ++i) entry_of_scratch_.emplace(entries_[i].contact, i);
    for (const auto& [contact, detection] : response_.fed()) {
        const std::size_t i = entry_of_scratch_.find(contact);
        if (i != PointerIndex<BarycentricPenaltyContact>::npos) step_start_[i].last_outputs = detection->outputs;
    }
}

void ContactPipeline::update_geometry(const Node& subtree) { update_geometry_if(&subtree); }

void ContactPipeline::update_geometry() { update_geometry_if(nullptr); }

void ContactPipeline::update_geometry_if(const Node* subtree) {
    if (!keep_step_start_)
        throw_invalid_argument("ContactPipeline::update_geometry: call attach_newton(solver) first (the pipeline must ",
                               "keep the pre-step contact state)");
    if (!snapshot_valid_)
        throw_invalid_argument("ContactPipeline::update_geometry: update() has not run since attach_newton (run one ",
                               "collision step first)");
    ++geometry_updates_;
    const auto in_subtree = [subtree](const Node* n) {
        if (subtree == nullptr) return true;
        for (; n != nullptr; n = n->parent())
            if (n == subtree) return true;
        return false;
    };
    std::vector<std::size_t> chosen;
    for (std::size_t i = 0; i < entries_.size(); ++i)
        if (in_subtree(entries_[i].host)) chosen.push_back(i);
    if (chosen.empty()) return;
    run_detection([&] {
        collision_.refit();
        for (const std::size_t i : chosen) {
            ContactGraphEntry& e = entries_[i];
            StepStart& st = step_start_[i];
            BarycentricPenaltyContact& contact = *e.contact;
            CollisionModel& m1 = *models_[model_index(contact.model1())].model;
            CollisionModel& m2 = *models_[model_index(contact.model2())].model;
            collision_.detect_pair(m1, m2, st.iterate_outputs);
            // Back to the state before this step's update(): the id map of the previous step
            // (rebuilt from the outputs that made it) and its contact list (ages, friction history,
            // dissipated energy) ...
            contact.set_detection_outputs(st.outputs_before);
            contact.force_field() = st.field_before;
            // ... then this step's contacts at the iterate's geometry, tracked against it.
            contact.set_detection_outputs(st.iterate_outputs);
            std::swap(st.last_outputs, st.iterate_outputs);
            evaluate_at_step_start(i);
            for (BaseMapping* m : e.mappings)
                if (m) m->init();
        }
    });
}

void ContactPipeline::swap_with_start(ModelEntry& e) {
    if (e.vec3) {
        std::swap(e.vec3->position, e.start_x);
        std::swap(e.vec3->velocity, e.start_v);
    } else {
        std::swap(e.rigid->position, e.start_rx);
        std::swap(e.rigid->velocity, e.start_rv);
    }
}

void ContactPipeline::evaluate_at_step_start(std::size_t entry) {
    // The first add_force of a step fixes the per-step friction anchor (u₀, ξ₀ = rotate(ξ_prev) +
    // h·P·(v2 − v1)) and counts the dissipated energy. For a rebuilt pair it is run here at the
    // start-of-step x_n, v_n (the contacts are the iterate's), so that, as without geometry
    // updates, the in-step tangential stretch is P·(u(x) − u(x_n)) and is consistent with the
    // sticking stiffness −kt·P the Newton matrix uses. Without friction and damping the first
    // evaluation has no effect and is skipped.
    BarycentricPenaltyContact& contact = *entries_[entry].contact;
    const PenaltyParameters& pp = contact.force_field().parameters();
    if (pp.friction != FrictionModel::coulomb && !(pp.damping > 0.0)) return;
    if (contact.force_field().size() == 0) return;
    ModelEntry& m1 = models_[model_index(contact.model1())];
    ModelEntry& m2 = models_[model_index(contact.model2())];
    const bool same_state = m1.node == m2.node;
    swap_with_start(m1);
    if (!same_state) swap_with_start(m2);
    const BaseState* s1 = m1.node->state();
    const BaseState* s2 = m2.node->state();
    std::vector<double> f1(s1->scalar_size(), 0.0);
    std::vector<double> f2(same_state ? 0 : s2->scalar_size(), 0.0);
    try {
        contact.add_force(f1, same_state ? std::span<double>(f1) : std::span<double>(f2));
    } catch (...) {
        swap_with_start(m1);
        if (!same_state) swap_with_start(m2);
        throw;
    }
    swap_with_start(m1);
    if (!same_state) swap_with_start(m2);
    contact.update_contact_points();
}

void ContactPipeline::keep_step_start() {
    if (keep_step_start_) return;
    // Live pairs were last fed by the last update(): their outputs are still in detections().
    keep_step_start_ = true;
    record_fed_outputs();
}

void ContactPipeline::attach_newton(EulerImplicitSolver& solver) {
    const Node* owner = nullptr;
    const auto search = [&](const auto& self, const Node& n) -> void {
        if (n.ode_solver() == &solver) owner = &n;
        for (const auto& c : n.children()) self(self, *c);
    };
    search(search, simulation_->root());
    if (owner == nullptr)
        throw_invalid_argument("ContactPipeline::attach_newton: the solver is not owned by a node of the simulation");
    keep_step_start();
    if (std::find(attached_solvers_.begin(), attached_solvers_.end(), &solver) == attached_solvers_.end())
        attached_solvers_.push_back(&solver);
    solver.newton.update_geometry = [this, owner] { update_geometry(*owner); };
}

const ContactGraphEntry* ContactPipeline::find(const CollisionModel& m1, const CollisionModel& m2) const {
    for (const auto& e : entries_)
        if (e.contact && &e.contact->model1() == &m1 && &e.contact->model2() == &m2) return &e;
    return nullptr;
}

Node* ContactPipeline::host_node(const CollisionModel& m1, const CollisionModel& m2) const {
    // Spec §2.1 (SubCollisionPipeline::computeCollisionResponse).
    if (!m1.params().simulated) return model_entry(m2).node;
    if (!m2.params().simulated) return model_entry(m1).node;
    (void)model_entry(m1);  // both must be registered here
    (void)model_entry(m2);
    return node_;
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
            if (!me.vec3)
                throw_invalid_argument("ContactPipeline: identity contact mapper on non-Vec3 model '", me.model->name(),
                                       "'");
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
    e.host = host_node(contact.model1(), contact.model2());
    auto ff = std::make_unique<PenaltyInteraction>(*e.point_states[0], *e.point_states[1], contact.force_field());
    e.force_field = ff.get();
    e.host->add_force_field_ptr(std::move(ff));
    if (entry_of_valid_) entry_of_.emplace(&contact, entries_.size());
    entries_.push_back(e);
    // A new pair's "before" state: no contact, no tracked id (its first set_detection_outputs
    // follows this hook).
    StepStart st;
    st.field_before = contact.force_field();
    step_start_.push_back(std::move(st));
}

void ContactPipeline::on_destroy(BarycentricPenaltyContact& contact) {
    // The entry found by a hash lookup and marked; remove_destroyed_entries (on_destroy_done)
    // takes the marked ones out of the graph and of entries_ in one pass each. (A search, two
    // erases from the node's lists and one from entries_ per destroyed pair were quadratic in
    // the live pairs: a pile of bodies loses hundreds a step.)
    if (!entry_of_valid_) {
        entry_of_.clear();
        for (std::size_t i = 0; i < entries_.size(); ++i)
            if (entries_[i].contact) entry_of_.emplace(entries_[i].contact, i);
        entry_of_valid_ = true;
    }
    const std::size_t i = entry_of_.find(&contact);
    if (i == PointerIndex<BarycentricPenaltyContact>::npos || entries_[i].contact != &contact) return;
    ContactGraphEntry& e = entries_[i];
    removed_fields_.emplace_back(e.host, e.force_field);
    for (Node* n : e.point_nodes)
        if (n) removed_nodes_.emplace_back(n->parent(), n);
    e.contact = nullptr;
    ++destroyed_entries_;
}

void ContactPipeline::remove_destroyed_entries() {
    entry_of_valid_ = false;  // entries_ moves below
    if (destroyed_entries_ == 0) return;
    // per node, its listed fields (children) in one pass; the others keep their order, as with
    // one removal per pair
    const auto remove_grouped = [](auto& removed, auto&& remove) {
        std::sort(removed.begin(), removed.end());
        std::vector<std::remove_cvref_t<decltype(removed.front().second)>> group;
        for (std::size_t g = 0; g < removed.size();) {
            Node* node = removed[g].first;
            group.clear();
            for (; g < removed.size() && removed[g].first == node; ++g) group.push_back(removed[g].second);
            remove(*node, group);
        }
        removed.clear();
    };
    remove_grouped(removed_fields_, [](Node& n, const auto& group) { n.remove_force_fields(group); });
    remove_grouped(removed_nodes_, [](Node& n, const auto& group) { n.remove_children(group); });
    std::size_t live = 0;
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        if (!entries_[i].contact) continue;
        if (live != i) {
            entries_[live] = entries_[i];
            step_start_[live] = std::move(step_start_[i]);
        }
        ++live;
    }
    entries_.resize(live);
    step_start_.erase(step_start_.begin() + std::ptrdiff_t(live), step_start_.end());
    destroyed_entries_ = 0;
}

}  // namespace penalty
