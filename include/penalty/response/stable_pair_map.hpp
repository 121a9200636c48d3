#pragma once
/// @file
/// StablePairMap: SOFA's helper::map_ptr_stable_compare over pairs of pointers, the container of
/// SOFA's narrow-phase outputs (NarrowPhaseDetection::DetectionOutputMap) and of its contacts
/// (CollisionResponse::contactMap), whose order is the order in which SOFA creates contacts and
/// re-adds their force fields to the graph (docs/sofa-compatibility.md, cause 16).
///
/// The map is a std::map keyed by (p1, p2) whose comparator does not compare the addresses: it
/// replaces each pointer by a *stable id*, 0, 1, 2 … in the order the pointers are first met by a
/// comparison (helper::ptr_stable_id), and orders keys by (id(p1), id(p2)). The ids belong to the
/// map and live as long as it (erase and clear keep them). So the order depends on the exact
/// sequence of comparisons the std::map makes, which is why this class wraps a real std::map and
/// offers only SOFA's calls: insert with the hint end() (NarrowPhaseDetection::getDetectionOutputs),
/// insert (CollisionResponse::createNewContacts), contains (removeInactiveContacts) and erase by
/// iterator (endNarrowPhase, removeInactiveContacts), which compares nothing. The same libstdc++
/// as SOFA's build makes the same comparisons. Consequences: a key inserted into an empty map is
/// compared with nothing and its pointers get ids only at a later comparison; a key found with
/// the hint end() needs one comparison when it goes after the last key.
///
/// Ids within one comparison: SOFA's comparator (ptr_stable_compare<std::pair<T*, T*>>) evaluates
/// make_pair(id(b.first), id(b.second)) > make_pair(id(a.first), id(a.second)); GCC 12 (-O0 and
/// -O2, C++17 and C++20, probed) evaluates the four ids right to left: a.second, a.first,
/// b.second, b.first. The comparator below calls them in that order explicitly.

#include "penalty/core/pointer_index.hpp"

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace penalty {

template <class T, class V>
class StablePairMap {
public:
    using Key = std::pair<const T*, const T*>;

private:
    /// helper::ptr_stable_id: the id of a pointer, given at its first request, 0, 1, 2 … (a null
    /// pointer too). A PointerIndex where SOFA uses a std::map: the ids depend only on the order
    /// of the requests, not on the lookup structure. The stored keys keep the ids they asked
    /// for (StoredKey), so few comparisons ask.
    struct Ids {
        PointerIndex<T> index;
        unsigned id(const T* p) { return static_cast<unsigned>(index.emplace(p, index.size()).first); }
    };
    /// A key as the map stores it: the two pointers and their ids once a comparison has asked
    /// for them. A pointer's id never changes once given, and asking again gives nothing new,
    /// so a comparison that reads a cached id instead of asking makes the same new ids in the
    /// same order: the cache only saves the lookups (a pile of bodies compares each key of its
    /// hundreds of model pairs about ten times a step, four lookups a comparison).
    struct StoredKey {
        static constexpr unsigned kNoId = ~0u;
        const T* first = nullptr;
        const T* second = nullptr;
        mutable unsigned first_id = kNoId;
        mutable unsigned second_id = kNoId;
        StoredKey(const Key& key) : first(key.first), second(key.second) {}  // NOLINT: a Key converts
        operator Key() const { return {first, second}; }                     // NOLINT: to and from
    };
    struct Less {
        Ids* ids;
        unsigned id(const T* p, unsigned& cached) const {
            if (cached == StoredKey::kNoId) cached = ids->id(p);
            return cached;
        }
        /// a < b ⟺ (id(a.first), id(a.second)) < (id(b.first), id(b.second)), ids requested in
        /// the order of SOFA's build (see the file comment).
        bool operator()(const StoredKey& a, const StoredKey& b) const {
            const unsigned a2 = id(a.second, a.second_id);
            const unsigned a1 = id(a.first, a.first_id);
            const unsigned b2 = id(b.second, b.second_id);
            const unsigned b1 = id(b.first, b.first_id);
            return std::make_pair(b1, b2) > std::make_pair(a1, a2);
        }
    };
    using Map = std::map<StoredKey, V, Less>;

public:
    using iterator = typename Map::iterator;
    using const_iterator = typename Map::const_iterator;

    StablePairMap() : ids_(std::make_unique<Ids>()), map_(Less{ids_.get()}) {}
    StablePairMap(StablePairMap&&) noexcept = default;
    StablePairMap& operator=(StablePairMap&&) noexcept = default;
    StablePairMap(const StablePairMap&) = delete;
    StablePairMap& operator=(const StablePairMap&) = delete;

    /// std::map::insert(end(), {key, value}): the existing entry when the key is present (its
    /// value unchanged), else the new one.
    iterator insert_at_end(const Key& key, V value) {
        if (spare_.empty()) return map_.insert(map_.end(), typename Map::value_type(key, std::move(value)));
        // a node kept by erase: the same comparisons as inserting the value (libstdc++'s
        // _M_get_insert_hint_unique_pos, then the insert-left test), without an allocation
        typename Map::node_type& node = spare_.back();
        node.key() = StoredKey(key);  // no ids cached
        node.mapped() = std::move(value);
        const iterator it = map_.insert(map_.end(), std::move(node));
        // NOLINTNEXTLINE(bugprone-use-after-move): a node handle a failed insert leaves unchanged
        if (node.empty()) spare_.pop_back();  // inserted; else the key was there and node is unchanged
        return it;
    }
    /// std::map::insert({key, value}): (the entry, true if inserted).
    std::pair<iterator, bool> insert(const Key& key, V value) {
        if (spare_.empty()) return map_.insert(typename Map::value_type(key, std::move(value)));
        typename Map::node_type& node = spare_.back();
        node.key() = StoredKey(key);
        node.mapped() = std::move(value);
        auto result = map_.insert(std::move(node));  // the node comes back in result when not inserted
        if (result.inserted) spare_.pop_back();
        else node = std::move(result.node);
        return {result.position, result.inserted};
    }
    [[nodiscard]] bool contains(const Key& key) const { return map_.contains(key); }
    /// std::map::erase(it) (no comparison); the node is kept for a later insertion.
    iterator erase(iterator it) {
        const iterator next = std::next(it);
        spare_.push_back(map_.extract(it));
        return next;
    }
    /// Every key goes; the ids stay.
    void clear() {
        map_.clear();
        spare_.clear();
    }

    [[nodiscard]] iterator begin() { return map_.begin(); }
    [[nodiscard]] iterator end() { return map_.end(); }
    [[nodiscard]] const_iterator begin() const { return map_.begin(); }
    [[nodiscard]] const_iterator end() const { return map_.end(); }
    [[nodiscard]] std::size_t size() const { return map_.size(); }
    [[nodiscard]] bool empty() const { return map_.empty(); }

    /// The stable id of `p`, if a comparison has met it (does not give one).
    [[nodiscard]] std::optional<unsigned> stable_id(const T* p) const {
        const std::size_t at = ids_->index.find(p);
        if (at == PointerIndex<T>::npos) return std::nullopt;
        return static_cast<unsigned>(at);
    }

private:
    std::unique_ptr<Ids> ids_;  // owned here: the comparator (copied into map_) points to it
    Map map_;
    std::vector<typename Map::node_type> spare_;  // erased nodes: steady steps allocate nothing
};

}  // namespace penalty
