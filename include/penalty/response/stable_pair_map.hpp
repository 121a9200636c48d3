#pragma once
/// @file
/// StablePairMap: SOFA's helper::map_ptr_stable_compare over pairs of pointers, the container of
/// SOFA's narrow-phase outputs (NarrowPhaseDetection::DetectionOutputMap) and of its contacts
/// (CollisionResponse::contactMap), whose order is the order in which SOFA creates contacts and
/// re-adds their force fields to the graph (docs/sofa-compatibility.md, cause 16).
///
/// SOFA's map is a std::map keyed by (p1, p2) whose comparator does not compare the addresses: it
/// replaces each pointer by a *stable id*, 0, 1, 2 … in the order the pointers are first met by a
/// comparison (helper::ptr_stable_id), and orders keys by (id(p1), id(p2)). The ids belong to the
/// map and live as long as it (erase and clear keep them). So the ids depend on the sequence of
/// comparisons libstdc++'s std::map makes. Only a call's *first* comparison can meet a pointer
/// without id: every later comparison of the call is between keys already compared. libstdc++'s
/// first comparisons (stl_tree.h, the library of SOFA's build):
/// - insert with the hint end() (NarrowPhaseDetection::getDetectionOutputs): comp(last key, k);
/// - insert (CollisionResponse::createNewContacts, _M_get_insert_unique_pos): comp(k, root);
/// - find / contains (removeInactiveContacts, _M_lower_bound): comp(root, k);
/// - into an empty map: none, and erase (endNarrowPhase, removeInactiveContacts) compares nothing.
/// Every key of a map of two keys or more has met a comparison (the second key's insertion
/// compares it with the first); only a lone key inserted into an empty map may have no ids, and
/// the next call's first comparison gives them. This class keeps the keys in a vector sorted by
/// their ids and asks for ids in exactly that sequence, so it gives SOFA's ids and order
/// (`tests/response/test_stable_pair_map.cpp` checks it against SOFA's calls on a std::map)
/// without a tree: a pile of bodies has thousands of pairs, each looked up several times a step.
///
/// Ids within one comparison: SOFA's comparator (ptr_stable_compare<std::pair<T*, T*>>) evaluates
/// make_pair(id(b.first), id(b.second)) > make_pair(id(a.first), id(a.second)); GCC 12 (-O0 and
/// -O2, C++17 and C++20, probed) evaluates the four ids right to left: a.second, a.first,
/// b.second, b.first. give_ids asks for a key's two ids in that order.

#include "penalty/core/pointer_index.hpp"
#include "penalty/core/radix_sort.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace penalty {

template <class T, class V>
class StablePairMap {
public:
    using Key = std::pair<const T*, const T*>;

    /// A key as the map stores it: the two pointers and their ids once a comparison has asked
    /// for them (only a lone key inserted into an empty map has none).
    struct StoredKey {
        static constexpr unsigned kNoId = ~0u;
        const T* first = nullptr;
        const T* second = nullptr;
        unsigned first_id = kNoId;
        unsigned second_id = kNoId;
        StoredKey() = default;
        StoredKey(const Key& key) : first(key.first), second(key.second) {}  // NOLINT: a Key converts
        operator Key() const { return {first, second}; }                     // NOLINT: to and from
        /// (id(first), id(second)) as one number, in the keys' order
        [[nodiscard]] std::uint64_t order() const { return (std::uint64_t(first_id) << 32) | second_id; }
    };
    using value_type = std::pair<StoredKey, V>;
    using iterator = typename std::vector<value_type>::iterator;
    using const_iterator = typename std::vector<value_type>::const_iterator;

    StablePairMap() = default;
    StablePairMap(StablePairMap&&) noexcept = default;
    StablePairMap& operator=(StablePairMap&&) noexcept = default;
    StablePairMap(const StablePairMap&) = delete;
    StablePairMap& operator=(const StablePairMap&) = delete;

    /// std::map::insert(end(), {key, value}): the existing entry when the key is present (its
    /// value unchanged), else the new one.
    iterator insert_at_end(const Key& key, V value) {
        if (entries_.empty()) return add_lone(key, std::move(value));
        give_lone_ids();  // comp(last key, k)
        StoredKey k(key);
        give_ids(k);
        return insert_sorted(k, std::move(value)).first;
    }
    /// std::map::insert({key, value}): (the entry, true if inserted).
    std::pair<iterator, bool> insert(const Key& key, V value) {
        if (entries_.empty()) return {add_lone(key, std::move(value)), true};
        StoredKey k(key);
        give_ids(k);  // comp(k, root)
        give_lone_ids();
        return insert_sorted(k, std::move(value));
    }
    /// std::map::contains(key) (gives `key`'s pointers ids, as SOFA's find does).
    [[nodiscard]] bool contains(const Key& key) {
        if (entries_.empty()) return false;
        give_lone_ids();  // comp(root, k)
        StoredKey k(key);
        give_ids(k);
        const auto it = lower_bound(k.order());
        return it != entries_.end() && it->first.order() == k.order();
    }
    /// std::map::erase(it) (no comparison).
    iterator erase(iterator it) {
        const auto at = it - entries_.begin();
        entries_.erase(it);
        lone_ = lone_ && !entries_.empty();
        return entries_.begin() + at;
    }
    /// Erases, in order, every entry for which erase(entry) is true (std::map::erase(it) over
    /// the map in order: no comparison), in one pass.
    template <class Pred>
    void erase_if(Pred erase) {
        std::size_t kept = 0;
        for (std::size_t i = 0; i < entries_.size(); ++i) {
            if (erase(entries_[i])) continue;
            if (kept != i) entries_[kept] = std::move(entries_[i]);
            ++kept;
        }
        entries_.resize(kept);
        lone_ = lone_ && !entries_.empty();
    }
    /// NarrowPhaseDetection's step on its outputs map, as one call: every value set to its empty
    /// value (beginNarrowPhase), `inserts` inserted in order with the hint end(), each assigning
    /// its value to its key's entry (getDetectionOutputs), then every entry whose value `keep`
    /// rejects erased (endNarrowPhase). The same ids and entries as those calls one by one.
    template <class Keep>
    void refill_at_end(std::span<const std::pair<Key, V>> inserts, Keep keep) {
        // the ids, asked for as the inserts' first comparisons ask: comp(last key, k)
        bool any = !entries_.empty();
        std::size_t lone_insert = inserts.size();  // a first key inserted into the empty map
        for (std::size_t i = 0; i < inserts.size(); ++i) {
            if (!any) {
                any = true;
                lone_insert = i;
                continue;
            }
            give_lone_ids();
            if (lone_insert < inserts.size()) {
                StoredKey lone(inserts[lone_insert].first);
                give_ids(lone);
                lone_insert = inserts.size();
            }
            StoredKey k(inserts[i].first);
            give_ids(k);
        }
        // the entries: every inserted key with its last value, kept or not, in the keys' order
        entries_.clear();
        lone_ = lone_insert < inserts.size();
        if (lone_) {
            if (keep(inserts[lone_insert].second))
                entries_.emplace_back(inserts[lone_insert].first, inserts[lone_insert].second);
            lone_ = !entries_.empty();
            return;
        }
        for (const auto& [key, value] : inserts) {
            StoredKey k(key);
            k.first_id = id_of(k.first);
            k.second_id = id_of(k.second);
            entries_.emplace_back(k, value);
        }
        if (entries_.size() < kMinEntriesForRadixSort) {
            // an insertion sort: stable, and without the radix sort's counters to clear
            for (std::size_t i = 1; i < entries_.size(); ++i)
                for (std::size_t j = i; j > 0 && entries_[j].first.order() < entries_[j - 1].first.order(); --j)
                    std::swap(entries_[j], entries_[j - 1]);
        } else {
            const int id_bits = std::max(1, int(std::bit_width(ids_.size())));
            stable_radix_sort(entries_, swap_, counts_, [id_bits](const value_type& e) {
                return (std::uint64_t(e.first.first_id) << id_bits) | e.first.second_id;
            });
        }
        std::size_t kept = 0;
        for (std::size_t i = 0; i < entries_.size(); ++i) {
            const bool last_of_key =
                i + 1 == entries_.size() || entries_[i + 1].first.order() != entries_[i].first.order();
            if (!last_of_key || !keep(entries_[i].second)) continue;
            if (kept != i) entries_[kept] = std::move(entries_[i]);
            ++kept;
        }
        entries_.resize(kept);
    }
    /// Every key goes; the ids stay.
    void clear() {
        entries_.clear();
        lone_ = false;
    }

    [[nodiscard]] iterator begin() { return entries_.begin(); }
    [[nodiscard]] iterator end() { return entries_.end(); }
    [[nodiscard]] const_iterator begin() const { return entries_.begin(); }
    [[nodiscard]] const_iterator end() const { return entries_.end(); }
    [[nodiscard]] std::size_t size() const { return entries_.size(); }
    [[nodiscard]] bool empty() const { return entries_.empty(); }

    /// The stable id of `p`, if a comparison has met it (does not give one).
    [[nodiscard]] std::optional<unsigned> stable_id(const T* p) const {
        const std::size_t at = ids_.find(p);
        if (at == PointerIndex<T>::npos) return std::nullopt;
        return static_cast<unsigned>(at);
    }

private:
    /// refill_at_end sorts fewer entries by insertion (a few model pairs: a radix pass clears
    /// 2 048 counters).
    static constexpr std::size_t kMinEntriesForRadixSort = 64;
    /// helper::ptr_stable_id: the id of a pointer, given at its first request, 0, 1, 2 … (a null
    /// pointer too).
    unsigned id_of(const T* p) { return static_cast<unsigned>(ids_.emplace(p, ids_.size()).first); }
    /// The ids of one comparison's key, asked for in the order of SOFA's build (file comment).
    void give_ids(StoredKey& k) {
        k.second_id = id_of(k.second);
        k.first_id = id_of(k.first);
    }
    /// A lone key meets its first comparison.
    void give_lone_ids() {
        if (!lone_) return;
        give_ids(entries_.front().first);
        lone_ = false;
    }
    iterator add_lone(const Key& key, V value) {
        entries_.emplace_back(StoredKey(key), std::move(value));
        lone_ = true;
        return entries_.begin();
    }
    iterator lower_bound(std::uint64_t order) {
        return std::lower_bound(entries_.begin(), entries_.end(), order,
                                [](const value_type& e, std::uint64_t o) { return e.first.order() < o; });
    }
    /// Every entry has its ids (no lone key).
    std::pair<iterator, bool> insert_sorted(const StoredKey& k, V value) {
        const auto it = lower_bound(k.order());
        if (it != entries_.end() && it->first.order() == k.order()) return {it, false};
        return {entries_.insert(it, value_type(k, std::move(value))), true};
    }

    PointerIndex<T> ids_;
    std::vector<value_type> entries_;  ///< sorted by (id(first), id(second)) but for a lone key
    bool lone_ = false;                ///< one entry, inserted into an empty map, never compared
    std::vector<value_type> swap_;     ///< refill_at_end's scratch
    std::vector<std::size_t> counts_;
};

}  // namespace penalty
