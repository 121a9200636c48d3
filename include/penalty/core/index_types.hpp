#pragma once
/// @file
/// Strong index types: an index says what it indexes. `DofIndex` (a DOF of a state: a row of its
/// positions), `ElementIndex` (an element of a collision model: a point, an edge, a triangle …)
/// and `ModelIndex` (a collision model's place in a pipeline) each wrap the integer of `Index`,
/// are built from it only explicitly, compare only with their own kind and do no arithmetic, so
/// an element cannot be passed where a DOF is expected. Zero cost: each is trivially copyable and
/// of the integer's size (checked below).
///
/// `PairKey`: two 32-bit indices (an element of each of two models, two models, two surfaces) as
/// one 64-bit key, the first in the high half. Its order is the order of that integer (the first
/// index, then the second), and its hash is the integer's: radix sorts take `bits()`, hash maps
/// and sorts find the keys in the order they always had. The packing lives here only.

#include <compare>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <ostream>
#include <type_traits>

namespace penalty {

/// An index of one kind (`Tag`): explicit from the integer, `value()` back, ordered among its
/// kind only.
template <class Tag>
class StrongIndex {
public:
    using value_type = std::int64_t;  ///< the integer of `Index` (types.hpp)

    constexpr StrongIndex() = default;
    constexpr explicit StrongIndex(value_type value) : value_(value) {}

    [[nodiscard]] constexpr value_type value() const { return value_; }
    /// The index as a subscript (a non-negative index).
    [[nodiscard]] constexpr std::size_t slot() const { return static_cast<std::size_t>(value_); }

    friend constexpr bool operator==(StrongIndex, StrongIndex) = default;
    // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the defaulted <=> (a false positive)
    friend constexpr auto operator<=>(StrongIndex, StrongIndex) = default;
    /// The number (messages, test failures).
    friend std::ostream& operator<<(std::ostream& out, StrongIndex index) { return out << index.value_; }

private:
    value_type value_ = 0;
};

/// A DOF of a state (a row of its positions, velocities and forces).
using DofIndex = StrongIndex<struct DofIndexTag>;
/// An element of a collision model (its points, edges, triangles, tetrahedra, spheres …).
using ElementIndex = StrongIndex<struct ElementIndexTag>;
/// A collision model's place in its pipeline (the order in which the pipeline lists them).
using ModelIndex = StrongIndex<struct ModelIndexTag>;

/// Two 32-bit indices, `first` in the high half of one 64-bit integer (`bits()`).
class PairKey {
public:
    constexpr PairKey() = default;
    /// (first, second), each below 2³².
    constexpr PairKey(std::uint32_t first, std::uint32_t second)
        : bits_(std::uint64_t(first) << 32 | std::uint64_t(second)) {}
    /// (first, second) of one kind of index, each in [0, 2³²).
    template <class Tag>
    constexpr PairKey(StrongIndex<Tag> first, StrongIndex<Tag> second)
        : PairKey(static_cast<std::uint32_t>(first.value()), static_cast<std::uint32_t>(second.value())) {}
    /// The key {min(a, b), max(a, b)}: an unordered pair.
    [[nodiscard]] static constexpr PairKey unordered(std::uint32_t a, std::uint32_t b) {
        return a < b ? PairKey(a, b) : PairKey(b, a);
    }
    /// The key whose integer is `bits` (a key stored as its integer, in a radix-sorted array).
    [[nodiscard]] static constexpr PairKey from_bits(std::uint64_t bits) {
        PairKey key;
        key.bits_ = bits;
        return key;
    }

    /// The index in the high half.
    [[nodiscard]] constexpr std::uint32_t first() const { return static_cast<std::uint32_t>(bits_ >> 32); }
    /// The index in the low half.
    [[nodiscard]] constexpr std::uint32_t second() const { return static_cast<std::uint32_t>(bits_); }
    /// first << 32 | second: what radix sorts and the candidate arrays hold.
    [[nodiscard]] constexpr std::uint64_t bits() const { return bits_; }

    friend constexpr bool operator==(PairKey, PairKey) = default;
    /// The order of bits(): by first, then second.
    // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the defaulted <=> (a false positive)
    friend constexpr auto operator<=>(PairKey, PairKey) = default;
    /// "(first, second)".
    friend std::ostream& operator<<(std::ostream& out, PairKey key) {
        return out << '(' << key.first() << ", " << key.second() << ')';
    }

private:
    std::uint64_t bits_ = 0;
};

static_assert(std::is_trivially_copyable_v<DofIndex> && sizeof(DofIndex) == sizeof(std::int64_t));
static_assert(std::is_trivially_copyable_v<ElementIndex> && sizeof(ElementIndex) == sizeof(std::int64_t));
static_assert(std::is_trivially_copyable_v<ModelIndex> && sizeof(ModelIndex) == sizeof(std::int64_t));
static_assert(std::is_trivially_copyable_v<PairKey> && sizeof(PairKey) == sizeof(std::uint64_t));
static_assert(!std::is_convertible_v<ElementIndex, DofIndex> && !std::is_convertible_v<DofIndex, ElementIndex>);
static_assert(!std::is_convertible_v<std::int64_t, ElementIndex> && !std::is_convertible_v<ElementIndex, std::int64_t>);

}  // namespace penalty

/// The hash of the integer (std::hash<Index>, std::hash<std::uint64_t>): the tables keyed by these
/// types place their keys where the integers went.
template <class Tag>
struct std::hash<penalty::StrongIndex<Tag>> {
    std::size_t operator()(penalty::StrongIndex<Tag> index) const noexcept {
        return std::hash<std::int64_t>{}(index.value());
    }
};
template <>
struct std::hash<penalty::PairKey> {
    std::size_t operator()(penalty::PairKey key) const noexcept { return std::hash<std::uint64_t>{}(key.bits()); }
};
