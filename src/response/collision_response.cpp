#include "penalty/response/collision_response.hpp"

#include "penalty/core/error.hpp"
#include "penalty/core/first_error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace penalty {

namespace {

using MT = ModelType;

constexpr std::pair<MT, MT> kRegistered[] = {
    {MT::Sphere, MT::Sphere},
    {MT::Sphere, MT::RigidSphere},
    {MT::RigidSphere, MT::RigidSphere},
    {MT::Sphere, MT::Point},
    {MT::RigidSphere, MT::Point},
    {MT::Point, MT::Point},
    {MT::Line, MT::Point},
    {MT::Line, MT::Line},
    {MT::Line, MT::Sphere},
    {MT::Line, MT::RigidSphere},
    {MT::Triangle, MT::Sphere},
    {MT::Triangle, MT::RigidSphere},
    {MT::Triangle, MT::Point},
    {MT::Triangle, MT::Line},
    {MT::Triangle, MT::Triangle},
    {MT::Cylinder, MT::Cylinder},
    {MT::Cylinder, MT::Triangle},
    {MT::Cylinder, MT::Sphere},
    {MT::Cylinder, MT::RigidSphere},
    {MT::Tetrahedron, MT::Sphere},
    {MT::Tetrahedron, MT::Point},
    {MT::Tetrahedron, MT::Line},
    {MT::Tetrahedron, MT::Triangle},
    {MT::Tetrahedron, MT::Tetrahedron},
};

double parse_double(std::string_view key, std::string_view value) {
    double v = 0.0;
    const auto* end = value.data() + value.size();
    const auto r = std::from_chars(value.data(), end, v);
    if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v))
        throw_invalid_argument("responseParams: parameter '", key, "': '", value, "' is not a finite number");
    return v;
}

std::pair<std::string_view, std::string_view> split_name(std::string_view name) {
    const auto q = name.find('?');
    if (q == std::string_view::npos) return {name, {}};
    return {name.substr(0, q), name.substr(q + 1)};
}

}  // namespace

bool is_penalty_response_pair(ModelType t1, ModelType t2) {
    return std::any_of(std::begin(kRegistered), std::end(kRegistered),
                       [&](const auto& p) { return p.first == t1 && p.second == t2; });
}

void apply_response_params(std::string_view params, ContactResponseParameters& p, std::vector<std::string>* unknown) {
    std::size_t start = 0;
    while (start <= params.size()) {
        std::size_t amp = params.find('&', start);
        if (amp == std::string_view::npos) amp = params.size();
        const std::string_view item = params.substr(start, amp - start);
        start = amp + 1;
        if (item.empty()) continue;
        const auto eq = item.find('=');
        if (eq == std::string_view::npos || eq == 0)
            throw_invalid_argument("responseParams: item '", item, "' is not name=value");
        const std::string_view key = item.substr(0, eq), value = item.substr(eq + 1);
        if (key == "damping") {
            p.penalty.damping = parse_double(key, value);
        } else if (key == "friction") {
            if (value == "ignored") p.penalty.friction = FrictionModel::ignored;
            else if (value == "coulomb") p.penalty.friction = FrictionModel::coulomb;
            else
                throw_invalid_argument("responseParams: parameter 'friction': '", value,
                                       "' (expected ignored or coulomb)");
        } else if (key == "tangentialStiffnessRatio" || key == "tangential_stiffness_ratio") {
            p.penalty.tangential_stiffness_ratio = parse_double(key, value);
        } else if (key == "tangentialDamping" || key == "tangential_damping") {
            p.penalty.tangential_damping = parse_double(key, value);
        } else if (key == "timeStep" || key == "time_step") {
            p.penalty.time_step = parse_double(key, value);
        } else if (key == "stiffnessLaw" || key == "stiffness_law") {
            if (value == "sofa") p.stiffness_law = StiffnessLaw::sofa;
            else if (value == "physical") p.stiffness_law = StiffnessLaw::physical;
            else
                throw_invalid_argument("responseParams: parameter 'stiffnessLaw': '", value,
                                       "' (expected sofa or physical)");
        } else if (key == "rigidSphereRadius" || key == "rigid_sphere_radius") {
            if (value == "head") p.rigid_sphere_radius = RigidSphereRadius::sofa_head;
            else if (value == "v26.06") p.rigid_sphere_radius = RigidSphereRadius::sofa_v26_06;
            else
                throw_invalid_argument("responseParams: parameter 'rigidSphereRadius': '", value,
                                       "' (expected head or v26.06)");
        } else if (unknown) {
            unknown->emplace_back(key);
        }
        if (amp == params.size()) break;
    }
    p.validate();
}

void check_response_name(std::string_view name) {
    const auto [key, params] = split_name(name);
    if (!key.empty() && key != kPenaltyResponseName && key != "nullptr")
        throw_invalid_argument("unknown response '", key, "' (available: ", kPenaltyResponseName, ", nullptr)");
    ContactResponseParameters check;
    apply_response_params(params, check, nullptr);
}

CollisionResponse::CollisionResponse(std::string response, std::string response_params,
                                     const ContactResponseParameters& base)
    : response_(std::move(response)), response_params_(std::move(response_params)), base_(base) {
    if (response_.empty()) {
        warnings_.emplace_back("CollisionResponse: no response method has been set: no contact will be created");
    } else if (response_ != kPenaltyResponseName && response_ != "nullptr") {
        throw_invalid_argument("CollisionResponse: parameter 'response': unknown response '", response_,
                               "' (available: ", kPenaltyResponseName, ", nullptr)");
    }
    base_.validate();
    // check the parameters once, up front
    ContactResponseParameters check = base_;
    apply_response_params(response_params_, check, nullptr);
}

std::string CollisionResponse::base_response_name() const {
    return response_params_.empty() ? response_ : response_ + "?" + response_params_;
}

std::string CollisionResponse::response_name(const CollisionModel& m1, const CollisionModel& m2) const {
    std::string base = base_response_name();
    const std::string& r1 = m1.params().contact_response;
    const std::string& r2 = m2.params().contact_response;
    if (r1.empty() && r2.empty()) return base;
    if (r1.empty()) return r2;
    if (r2.empty()) return r1;
    return r1 == r2 ? r1 : base;
}

std::unique_ptr<BarycentricPenaltyContact> CollisionResponse::create_contact(const std::string& name,
                                                                             const CollisionModel& m1,
                                                                             const CollisionModel& m2,
                                                                             double intersection_cd) {
    const auto [key, params] = split_name(name);
    if (key.empty() || key == "nullptr") return nullptr;
    if (key != kPenaltyResponseName)
        throw_invalid_argument("CollisionResponse: models '", m1.name(), "' and '", m2.name(), "': unknown response '",
                               key, "'");
    if (!is_penalty_response_pair(m1.type(), m2.type())) {
        warnings_.push_back(std::string("CollisionResponse: contact ") + std::string(key) + " between '" + m1.name() +
                            "' (" + model_type_name(m1.type()) + ") and '" + m2.name() + "' (" +
                            model_type_name(m2.type()) + ") creation failed: pair not registered");
        return nullptr;
    }
    ContactResponseParameters p = base_;
    std::vector<std::string> unknown;
    apply_response_params(params, p, &unknown);
    for (const auto& u : unknown)
        warnings_.push_back("CollisionResponse: responseParams: parameter '" + u + "' not found");
    return std::make_unique<BarycentricPenaltyContact>(m1, m2, intersection_cd, p);
}

void CollisionResponse::set_detections(std::span<const ModelPairDetection> detections, double intersection_cd) {
    if (!sofa_stable_id_order) {
        set_detections_by_rank(detections, intersection_cd);
        return;
    }
    // SOFA's two maps, fed with SOFA's calls in SOFA's order: their stable ids decide the order
    // of creation and of the contact vector (stable_pair_map.hpp). Nothing else here may look a
    // key up in them: a comparison gives ids.
    // NarrowPhaseDetection::beginNarrowPhase, then BVHNarrowPhase::addCollisionPair →
    // getDetectionOutputs for every pair the broad phase passes (in its order, registered order
    // within the pair), with or without outputs, inserted with the hint end(), then
    // endNarrowPhase: the pairs without outputs leave the map.
    refill_.clear();
    for (const ModelPairDetection& d : detections)
        if (!d.skipped && d.narrow_phase && d.model1 && d.model2)
            refill_.emplace_back(ModelPair{d.model1, d.model2}, &d);
    outputs_map_.refill_at_end(std::span<const std::pair<ModelPair, const ModelPairDetection*>>(refill_),
                               [](const ModelPairDetection* d) { return d != nullptr && !d->outputs.empty(); });
    // CollisionResponse::createNewContacts, in the outputs map's order.
    feed_.clear();
    // the pairs refused a contact are searched only when there are some (a search of every
    // pair per new pair was quadratic in the live pairs)
    const bool any_refused =
        std::any_of(pairs_.begin(), pairs_.end(), [](const ContactPairEntry& e) { return !e.contact; });
    for (const auto& [models, d] : outputs_map_) {
        const auto [it, inserted] = contact_map_.insert(models, nullptr);
        if (!inserted) {  // a live contact
            feed_.emplace_back(it->second, d);
            continue;
        }
        // (a copy of the key: a structured binding cannot be captured by a lambda before C++20's
        // P1091, which clang 14 lacks)
        const auto key = models;
        const auto refused =
            !any_refused ? pairs_.end() : std::find_if(pairs_.begin(), pairs_.end(), [&](const ContactPairEntry& e) {
                return !e.contact && e.model1 == key.first && e.model2 == key.second;
            });
        const bool refused_before = refused != pairs_.end();
        if (!refused_before) {
            ContactPairEntry e;
            e.model1 = d->model1;
            e.model2 = d->model2;
            e.response = response_name(*d->model1, *d->model2);
            e.contact = create_contact(e.response, *d->model1, *d->model2, intersection_cd);
            if (e.contact) {
                it->second = e.contact.get();
                if (on_create) on_create(*e.contact);
                feed_.emplace_back(e.contact.get(), d);
            }
            pairs_.push_back(std::move(e));
            if (it->second != nullptr) continue;
        }
        // no contact ("nullptr" response, pair not registered): SOFA drops the key again, and
        // penalty keeps the pair (no contact, one warning) while it has outputs
        contact_map_.erase(it);
        ordered_.push_back(std::move(refused_before ? *refused : pairs_.back()));
    }
    // CollisionResponse::removeInactiveContacts: contacts whose pair has no outputs now.
    contact_map_.erase_if([this](const auto& entry) {
        if (outputs_map_.contains(entry.first)) return false;
        if (on_destroy) on_destroy(*entry.second);
        return true;
    });
    if (on_destroy_done) on_destroy_done();  // the destroyed contacts are freed below (ordered_.clear())
    // CollisionResponse::createContacts: the contact vector in the contact map's order (the
    // order of the force fields in the graph), then the pairs without contact still detected.
    const std::size_t refused_count = ordered_.size();
    // each live contact's entry found by a binary search (a search of pairs_ per contact was
    // quadratic in the contacts)
    place_of_.clear();
    for (std::size_t i = 0; i < pairs_.size(); ++i)
        if (pairs_[i].contact) place_of_.emplace_back(pairs_[i].contact.get(), i);
    std::sort(place_of_.begin(), place_of_.end());
    for (const auto& [models, contact] : contact_map_) {
        const auto e = std::lower_bound(place_of_.begin(), place_of_.end(),
                                        std::pair<const BarycentricPenaltyContact*, std::size_t>(contact, 0));
        PENALTY_DEMAND(e != place_of_.end() && e->first == contact);
        ordered_.push_back(std::move(pairs_[e->second]));
    }
    std::rotate(ordered_.begin(), ordered_.begin() + std::ptrdiff_t(refused_count), ordered_.end());
    pairs_.swap(ordered_);
    ordered_.clear();  // the destroyed contacts and the pairs no longer detected
    feed_contacts();
}

void CollisionResponse::set_detections_by_rank(std::span<const ModelPairDetection> detections, double intersection_cd) {
    // buffers kept from step to step: with the same live pairs, a step allocates nothing here
    seen_.assign(pairs_.size(), 0);
    created_.clear();
    feed_.clear();
    for (const ModelPairDetection& d : detections) {
        if (d.skipped || d.outputs.empty() || !d.model1 || !d.model2) continue;
        const auto same_pair = [&d](const ContactPairEntry& e) { return e.model1 == d.model1 && e.model2 == d.model2; };
        auto it = std::find_if(pairs_.begin(), pairs_.end(), same_pair);
        if (it != pairs_.end()) {
            seen_[std::size_t(it - pairs_.begin())] = 1;
            if (it->contact) feed_.emplace_back(it->contact.get(), &d);
            continue;
        }
        auto ct = std::find_if(created_.begin(), created_.end(), same_pair);
        if (ct != created_.end()) {
            if (ct->contact) feed_.emplace_back(ct->contact.get(), &d);
            continue;
        }
        ContactPairEntry e;
        e.model1 = d.model1;
        e.model2 = d.model2;
        e.response = response_name(*d.model1, *d.model2);
        e.contact = create_contact(e.response, *d.model1, *d.model2, intersection_cd);
        if (e.contact) feed_.emplace_back(e.contact.get(), &d);
        created_.push_back(std::move(e));
    }
    // pairs without outputs this step: destroyed (SOFA's cleanup), the others keep their order
    if (on_destroy)
        for (std::size_t i = 0; i < pairs_.size(); ++i)
            if (!seen_[i] && pairs_[i].contact) on_destroy(*pairs_[i].contact);
    if (on_destroy_done) on_destroy_done();  // before the compaction below frees them
    std::size_t live = 0;
    for (std::size_t i = 0; i < pairs_.size(); ++i) {
        if (seen_[i]) {
            if (live != i) pairs_[live] = std::move(pairs_[i]);
            ++live;
        }
    }
    pairs_.erase(pairs_.begin() + std::ptrdiff_t(live), pairs_.end());
    // SOFA's contact-map order (model_rank): new pairs are created in it and merged into it; the
    // merge is stable, so without model_rank the new pairs follow the old ones in creation order.
    const auto before = [this](const ContactPairEntry& a, const ContactPairEntry& b) {
        if (!model_rank) return false;
        const std::size_t a1 = model_rank(*a.model1), b1 = model_rank(*b.model1);
        return a1 != b1 ? a1 < b1 : model_rank(*a.model2) < model_rank(*b.model2);
    };
    if (!created_.empty()) std::stable_sort(created_.begin(), created_.end(), before);
    const std::size_t old_count = pairs_.size();
    for (auto& e : created_) {
        if (e.contact && on_create) on_create(*e.contact);
        pairs_.push_back(std::move(e));
    }
    created_.clear();
    if (old_count != pairs_.size())
        std::inplace_merge(pairs_.begin(), pairs_.begin() + std::ptrdiff_t(old_count), pairs_.end(), before);
    feed_contacts();
}

void CollisionResponse::feed_contacts() {
    // Each contact's tracking, contact points and springs read its pair's outputs, its models
    // and their states, and write only the contact (its tracker, mappers and force field): the
    // contacts are fed in parallel, in the calling task arena, when it has more than one
    // thread and the step has at least 2·kMinOutputsPerConcurrentFeed outputs in two contacts
    // or more (below that a task costs more than it saves; TBB's partitioner groups small
    // contacts into one task). Same bits either way; a failing contact's exception is the first
    // in feed order.
    std::size_t outputs = 0;
    for (const auto& [c, d] : feed_) outputs += d->outputs.size();
    last_feed_concurrent_ = feed_.size() >= 2 && outputs >= 2 * kMinOutputsPerConcurrentFeed &&
                            tbb::this_task_arena::max_concurrency() >= 2;
    if (!last_feed_concurrent_) {
        for (auto& [c, d] : feed_) c->set_detection_outputs(d->outputs);
        return;
    }
    FirstErrorInOrder failure;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, feed_.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i)
                if (!failure.run(i, [&] { feed_[i].first->set_detection_outputs(feed_[i].second->outputs); })) return;
        });
    failure.rethrow_if_any();
}

void CollisionResponse::clear() {
    for (auto& e : pairs_)
        if (e.contact && on_destroy) on_destroy(*e.contact);
    if (on_destroy_done) on_destroy_done();
    pairs_.clear();
    contact_map_.clear();  // CollisionResponse::cleanup; the ids stay
}

BarycentricPenaltyContact* CollisionResponse::find(const CollisionModel& m1, const CollisionModel& m2) const {
    for (const auto& e : pairs_)
        if (e.model1 == &m1 && e.model2 == &m2) return e.contact.get();
    return nullptr;
}

std::vector<PairTimeScale> CollisionResponse::time_scales(
    const std::function<double(const CollisionModel&)>& mass_of) const {
    std::vector<PairTimeScale> out;
    for (const auto& e : pairs_) {
        if (!e.contact) continue;
        const double k = e.contact->max_stiffness();
        out.push_back({e.model1->type(), e.model2->type(), e.model1->name(), e.model2->name(), k,
                       contact_critical_time_step(k, mass_of(*e.model1), mass_of(*e.model2))});
    }
    return out;
}

}  // namespace penalty
