// StablePairMap (SOFA's helper::map_ptr_stable_compare over pointer pairs) and the contact order
// CollisionResponse takes from it. The expected orders are derived by hand from the rules of the
// comparator (ids in the order pointers are first met; per comparison a.second, a.first,
// b.second, b.first) and of libstdc++'s std::map (insert with the hint end(): one comparison
// with the last key, then the insert-left test; a key inserted into an empty map meets nothing).
#include "penalty/response/collision_response.hpp"
#include "penalty/response/stable_pair_map.hpp"

#include "../collision/fixtures.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <span>
#include <vector>

namespace penalty {
namespace {

using test::make_state;
using test::named;

struct Obj {
    int rank;
};
using Map = StablePairMap<Obj, int>;

template <class M>
std::vector<std::pair<int, int>> ranks_in_order(const M& m) {
    std::vector<std::pair<int, int>> out;
    for (const auto& [key, value] : m) out.emplace_back(key.first->rank, key.second->rank);
    return out;
}

// Objects A, B, C with ranks (scene order) 0, 1, 2. The outputs map receives (C, A) then (B, A)
// with the hint end(): (C, A) enters the empty map without a comparison; (B, A) is compared with
// the last key (C, A) as comp((C, A), (B, A)), which gives A id 0, C id 1, B id 2, so (B, A) =
// (2, 0) goes after (C, A) = (1, 0). Rank order would put (B, A) first.
TEST(StablePairMap, OrdersByFirstComparisonNotByRank) {
    Obj a{0}, b{1}, c{2};
    Map outputs;
    outputs.insert_at_end({&c, &a}, 1);
    EXPECT_FALSE(outputs.stable_id(&a));  // inserted into an empty map: no comparison
    EXPECT_FALSE(outputs.stable_id(&c));
    outputs.insert_at_end({&b, &a}, 2);
    EXPECT_EQ(outputs.stable_id(&a), 0u);
    EXPECT_EQ(outputs.stable_id(&c), 1u);
    EXPECT_EQ(outputs.stable_id(&b), 2u);
    EXPECT_EQ(ranks_in_order(outputs), (std::vector<std::pair<int, int>>{{2, 0}, {1, 0}}));

    // The contact map receives the same keys in the outputs map's order, without hint: (C, A)
    // into the empty map, then (B, A) compared with the root (C, A) as comp((B, A), (C, A)):
    // A id 0, B id 1, C id 2, so (B, A) goes first. The two maps order the same keys differently.
    Map contacts;
    for (const auto& [key, value] : outputs) EXPECT_TRUE(contacts.insert(key, value).second);
    EXPECT_EQ(contacts.stable_id(&a), 0u);
    EXPECT_EQ(contacts.stable_id(&b), 1u);
    EXPECT_EQ(contacts.stable_id(&c), 2u);
    EXPECT_EQ(ranks_in_order(contacts), (std::vector<std::pair<int, int>>{{1, 0}, {2, 0}}));

    // An existing key is found, not replaced; ids outlive erase and clear.
    EXPECT_FALSE(contacts.insert({&b, &a}, 7).second);
    EXPECT_EQ(contacts.begin()->second, 2);
    contacts.erase(contacts.begin());
    contacts.clear();
    EXPECT_TRUE(contacts.empty());
    EXPECT_EQ(contacts.stable_id(&c), 2u);
    // A later key with B first: (B, C) = (1, 2) goes before (C, A) = (2, 0) although it came
    // after it.
    contacts.insert({&c, &a}, 1);
    contacts.insert({&b, &c}, 3);
    EXPECT_EQ(ranks_in_order(contacts), (std::vector<std::pair<int, int>>{{1, 2}, {2, 0}}));
    EXPECT_TRUE(contacts.contains({&b, &c}));
    EXPECT_FALSE(contacts.contains({&a, &b}));
}

// SOFA's own calls on a std::map with SOFA's comparator: the reference that StablePairMap (which
// reuses erased nodes) must follow comparison for comparison. SOFA writes the comparator as
// make_pair(id(b.first), id(b.second)) > make_pair(id(a.first), id(a.second)), whose order of
// evaluation C++ leaves open; SOFA's build (g++) takes the ids right to left, written out below so
// that the reference is the same under every compiler (clang takes them left to right).
struct SofaIds {
    std::map<const Obj*, unsigned> of;
    unsigned next = 0;
    unsigned id(const Obj* p) {
        const auto it = of.find(p);
        if (it != of.end()) return it->second;
        of.emplace(p, next);
        return next++;
    }
};
struct SofaLess {
    SofaIds* ids;
    bool operator()(const std::pair<const Obj*, const Obj*>& a, const std::pair<const Obj*, const Obj*>& b) const {
        const unsigned a2 = ids->id(a.second), a1 = ids->id(a.first);
        const unsigned b2 = ids->id(b.second), b1 = ids->id(b.first);
        return std::make_pair(b1, b2) > std::make_pair(a1, a2);
    }
};

// 7 objects (many repeated keys), and 3 000 (the ids' table grows several times).
void same_order_and_ids_as_sofas_calls(int count, int steps) {
    std::vector<Obj> objs(std::size_t(count), Obj{0});
    for (int i = 0; i < count; ++i) objs[std::size_t(i)].rank = i;
    std::mt19937 rng(13);
    SofaIds ids_hint, ids_plain;
    std::map<std::pair<const Obj*, const Obj*>, int, SofaLess> ref_hint(SofaLess{&ids_hint});
    std::map<std::pair<const Obj*, const Obj*>, int, SofaLess> ref_plain(SofaLess{&ids_plain});
    Map hint, plain;
    for (int step = 0; step < steps; ++step) {
        const Obj* p = &objs[rng() % unsigned(count)];
        const Obj* q = &objs[rng() % unsigned(count)];
        switch (rng() % 4) {
            case 0:
            case 1:  // NarrowPhaseDetection::getDetectionOutputs / CollisionResponse::createNewContacts
                ref_hint.insert(ref_hint.end(), {{p, q}, step});
                hint.insert_at_end({p, q}, step);
                ref_plain.insert(decltype(ref_plain)::value_type({p, q}, step));
                plain.insert({p, q}, step);
                break;
            case 2:  // endNarrowPhase / removeInactiveContacts: erase the n-th entry
                if (!ref_hint.empty()) {
                    const std::size_t n = rng() % ref_hint.size();
                    ref_hint.erase(std::next(ref_hint.begin(), std::ptrdiff_t(n)));
                    hint.erase(std::next(hint.begin(), std::ptrdiff_t(n)));
                }
                if (!ref_plain.empty()) {
                    const std::size_t n = rng() % ref_plain.size();
                    ref_plain.erase(std::next(ref_plain.begin(), std::ptrdiff_t(n)));
                    plain.erase(std::next(plain.begin(), std::ptrdiff_t(n)));
                }
                break;
            default:  // removeInactiveContacts' outputsMap.contains
                EXPECT_EQ(ref_hint.contains({p, q}), hint.contains({p, q}));
                EXPECT_EQ(ref_plain.contains({p, q}), plain.contains({p, q}));
        }
        if (count > 100 && step % 97 != 0) continue;  // the full comparisons now and then
        ASSERT_EQ(ranks_in_order(ref_hint), ranks_in_order(hint)) << "step " << step;
        ASSERT_EQ(ranks_in_order(ref_plain), ranks_in_order(plain)) << "step " << step;
        for (const Obj& o : objs) {
            const auto h = ids_hint.of.find(&o);
            EXPECT_EQ(h == ids_hint.of.end() ? std::nullopt : std::optional<unsigned>(h->second), hint.stable_id(&o));
            const auto g = ids_plain.of.find(&o);
            EXPECT_EQ(g == ids_plain.of.end() ? std::nullopt : std::optional<unsigned>(g->second), plain.stable_id(&o));
        }
    }
    ASSERT_EQ(ranks_in_order(ref_hint), ranks_in_order(hint));
    ASSERT_EQ(ranks_in_order(ref_plain), ranks_in_order(plain));
    EXPECT_GT(ids_hint.of.size(), std::size_t(count) * 9 / 10);  // nearly every object got an id
}

TEST(StablePairMap, SameOrderAndIdsAsSofasCallsOnAStdMap) { same_order_and_ids_as_sofas_calls(7, 200); }

TEST(StablePairMap, SameOrderAndIdsAsSofasCallsWithThousandsOfPointers) {
    same_order_and_ids_as_sofas_calls(3000, 20000);
}

// NarrowPhaseDetection's step (beginNarrowPhase, getDetectionOutputs' inserts with the hint
// end(), endNarrowPhase) and CollisionResponse's removeInactiveContacts (contains on the outputs
// map, erase in order) as SOFA calls them on std::maps, against refill_at_end and erase_if: the
// same ids and order at every step. Steps of zero, one and a few pairs make and meet lone keys
// (inserted into an empty map, without ids), steps of 64 pairs or more the radix sort's path; the
// pairs are drawn from 20 objects of a window that moves over 1 000, so new pointers keep coming
// and meet lone keys.
TEST(StablePairMap, RefillAndEraseIfGiveTheIdsAndOrderOfSofasCallsOneByOne) {
    constexpr int kCount = 1000;
    std::vector<Obj> objs(kCount, Obj{0});
    for (int i = 0; i < kCount; ++i) objs[std::size_t(i)].rank = i;
    std::mt19937 rng(29);
    SofaIds ref_output_ids, ref_contact_ids;
    std::map<std::pair<const Obj*, const Obj*>, int, SofaLess> ref_outputs(SofaLess{&ref_output_ids});
    std::map<std::pair<const Obj*, const Obj*>, int, SofaLess> ref_contacts(SofaLess{&ref_contact_ids});
    Map outputs, contacts;
    int lone_steps = 0, new_lone_keys = 0, removed = 0, large_steps = 0;
    for (int step = 0; step < 3000; ++step) {
        // this step's detections: (pair, has outputs), with repeated pairs now and then
        std::vector<std::pair<std::pair<const Obj*, const Obj*>, int>> inserts;
        // mostly a few pairs (sorted by insertion), now and then 64 to 127 (a radix sort)
        const unsigned n = rng() % 4 == 0 ? rng() % 2 : rng() % 8 == 0 ? 64 + rng() % 64 : rng() % 12;
        large_steps += n >= 64 ? 1 : 0;
        const auto pick = [&] { return &objs[(unsigned(step) / 3 + rng() % 20) % kCount]; };
        for (unsigned i = 0; i < n; ++i) {
            const Obj* p = pick();
            inserts.push_back({{p, pick()}, int(rng() % 3 == 0 ? 0 : 1 + step)});
        }
        if (ref_outputs.empty() && inserts.size() == 1) {
            ++lone_steps;
            new_lone_keys += !outputs.stable_id(inserts[0].first.first) || !outputs.stable_id(inserts[0].first.second);
        }
        for (auto& e : ref_outputs) e.second = 0;
        for (const auto& [key, value] : inserts) ref_outputs.insert(ref_outputs.end(), {key, 0})->second = value;
        for (auto it = ref_outputs.begin(); it != ref_outputs.end();)
            it = it->second == 0 ? ref_outputs.erase(it) : std::next(it);
        outputs.refill_at_end(std::span<const std::pair<Map::Key, int>>(inserts), [](int v) { return v != 0; });
        // the contact map takes the outputs map's keys, then drops those that left it
        for (const auto& [key, value] : ref_outputs) ref_contacts.insert({key, value});
        for (const auto& [key, value] : outputs) contacts.insert(key, value);
        for (auto it = ref_contacts.begin(); it != ref_contacts.end();) {
            if (ref_outputs.contains(it->first)) {
                ++it;
            } else {
                it = ref_contacts.erase(it);
                ++removed;
            }
        }
        contacts.erase_if([&](const auto& entry) { return !outputs.contains(entry.first); });
        ASSERT_EQ(ranks_in_order(ref_outputs), ranks_in_order(outputs)) << "step " << step;
        ASSERT_EQ(ranks_in_order(ref_contacts), ranks_in_order(contacts)) << "step " << step;
        std::vector<int> ref_values, values;
        for (const auto& [key, value] : ref_outputs) ref_values.push_back(value);
        for (const auto& [key, value] : outputs) values.push_back(value);
        ASSERT_EQ(ref_values, values) << "step " << step;
        for (const Obj& o : objs) {
            const auto r = ref_output_ids.of.find(&o);
            ASSERT_EQ(r == ref_output_ids.of.end() ? std::nullopt : std::optional<unsigned>(r->second),
                      outputs.stable_id(&o));
            const auto c = ref_contact_ids.of.find(&o);
            ASSERT_EQ(c == ref_contact_ids.of.end() ? std::nullopt : std::optional<unsigned>(c->second),
                      contacts.stable_id(&o));
        }
    }
    EXPECT_GT(lone_steps, 50);     // keys inserted into an empty map
    EXPECT_GT(new_lone_keys, 10);  // with a pointer that had no id yet
    EXPECT_GT(large_steps, 200);   // steps of 64 pairs or more, repeated pairs among them
    EXPECT_GT(removed, 1000);      // and contacts removed
}

// A null pointer gets its id at its first comparison like any other (SOFA's ptr_stable_id keys
// its std::map by the pointer, null included): the same ids and order as SOFA's calls.
TEST(StablePairMap, ANullPointerGetsItsIdInTurn) {
    Obj a{0}, b{1};
    SofaIds ids;
    std::map<std::pair<const Obj*, const Obj*>, int, SofaLess> ref(SofaLess{&ids});
    Map m;
    const std::vector<std::pair<const Obj*, const Obj*>> keys = {
        {&a, &b}, {nullptr, &a}, {&b, nullptr}, {nullptr, nullptr}, {&a, nullptr}};
    for (std::size_t i = 0; i < keys.size(); ++i) {
        ref.insert(decltype(ref)::value_type(keys[i], int(i)));
        m.insert(keys[i], int(i));
    }
    std::vector<int> ref_order, order;
    for (const auto& [key, value] : ref) ref_order.push_back(value);
    for (const auto& [key, value] : m) order.push_back(value);
    EXPECT_EQ(order, ref_order);
    for (const Obj* o : std::vector<const Obj*>{&a, &b, nullptr}) {
        ASSERT_TRUE(ids.of.contains(o));
        EXPECT_EQ(m.stable_id(o), ids.of.at(o));
    }
    // the second key (null, A) against the first (A, B) asks, in order, A (0), null (1), B (2)
    EXPECT_EQ(m.stable_id(&a), 0u);
    EXPECT_EQ(m.stable_id(nullptr), 1u);
    EXPECT_EQ(m.stable_id(&b), 2u);
}

// CollisionResponse: a floor (Triangle) A under two spheres C and B, met by the broad phase as
// (A, C) then (A, B) (SOFA's models in the order C, B, A: each new model is paired with the earlier
// ones). The outputs map orders them (A, C), (A, B) (comp((A, C), (A, B)): C 0, A 1, B 2), so the
// contact of C is created first; the contact map orders (A, B) first (comp((A, B), (A, C)): B 0,
// A 1, C 2), which is the order of pairs() and so of the force fields in the graph.
TEST(CollisionResponse, CreatesInOutputsMapOrderAndListsInContactMapOrder) {
    std::unique_ptr<test::Mesh> mesh = test::triangle_mesh({{-5, 0, -5}, {5, 0, -5}, {0, 0, 5}}, {{0, 2, 1}});
    Vec3State ball_b = make_state({{0.2, 0.9, 0.3}});
    Vec3State ball_c = make_state({{-0.5, 0.9, -0.2}});
    TriangleModel floor{mesh->state, mesh->topo, named("floor")};
    SphereModel b{ball_b, 0.5, {}, named("b")};
    SphereModel c{ball_c, 0.5, {}, named("c")};
    const IntersectionParams params = IntersectionParams::new_proximity();
    CollisionResponse r;
    r.sofa_stable_id_order = true;
    std::vector<const CollisionModel*> created;
    r.on_create = [&](BarycentricPenaltyContact& contact) { created.push_back(&contact.model2()); };
    const auto step = [&] {
        const std::vector<ModelPairDetection> d = {detect_model_pair(params, floor, c),
                                                   detect_model_pair(params, floor, b)};
        ASSERT_FALSE(d[0].outputs.empty());
        ASSERT_FALSE(d[1].outputs.empty());
        r.set_detections(d, params.contact_distance);
    };
    step();
    ASSERT_EQ(created.size(), 2u);
    EXPECT_EQ(created[0], &c);
    EXPECT_EQ(created[1], &b);
    ASSERT_EQ(r.pairs().size(), 2u);
    EXPECT_EQ(r.pairs()[0].model2, &b);
    EXPECT_EQ(r.pairs()[1].model2, &c);
    step();  // the same pairs: nothing created, same order
    EXPECT_EQ(created.size(), 2u);
    ASSERT_EQ(r.pairs().size(), 2u);
    EXPECT_EQ(r.pairs()[0].model2, &b);
    EXPECT_EQ(r.pairs()[1].model2, &c);
}

}  // namespace
}  // namespace penalty
