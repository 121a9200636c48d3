// SOFA's read of a number Data: sofa::core::objectmodel::Data<T>::read (Data.h) extracts the value
// with `std::istringstream istr(s); istr >> value;` and fails only when the extraction fails, so
// text after a number is ignored: `tolerance="10-3"` reads 10 (SofaPython3's emptyForceField.py
// writes it). penalty reproduces this for one-number attributes (AttributeKind::real), with a
// warning; the SOFA quirk fix `number_trailing_text` keeps such a value an error.
#include "penalty/collision/intersection.hpp"
#include "penalty/scene/components.hpp"

#include "io/text.hpp"

#include <algorithm>
#include <cctype>

namespace penalty::scene {

namespace {

/// The longest prefix of `text` that `istream >> double` (libstdc++'s num_get, "C" locale)
/// reads: [sign] digits [. digits] [(e|E) [sign] digits]. 0 when it reads nothing or fails (an
/// exponent mark without digits fails the whole read: num_get hands "1e" to strtod, which
/// rejects it).
std::size_t number_prefix(std::string_view text) {
    std::size_t i = 0;
    const auto digits = [&] {
        const std::size_t start = i;
        while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) != 0) ++i;
        return i - start;
    };
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    std::size_t mantissa = digits();
    if (i < text.size() && text[i] == '.') {
        ++i;
        mantissa += digits();
    }
    if (mantissa == 0) return 0;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        if (digits() == 0) return 0;
    }
    return i;
}

const AttributeSpec* declared(const ComponentSpec& spec, std::string_view name) {
    for (const AttributeSpec& a : spec.attributes)
        if (a.name == name) return &a;
    for (const AttributeSpec& a : spec.shared_attributes)
        if (a.name == name) return &a;
    return nullptr;
}

/// Attributes SOFA reads in a component's parse() with BaseObjectDescription::getAttributeAsFloat,
/// not Data<T>::read: a value with text after its number gives the default there (the builder
/// reads them so: MechanicalObject::parse, RegularGridTopology::parse).
bool read_in_parse(std::string_view type, std::string_view attribute) {
    static constexpr std::string_view kMechanicalObject[] = {"dx", "dy",    "dz", "rx", "ry",
                                                             "rz", "scale", "sx", "sy", "sz"};
    static constexpr std::string_view kRegularGrid[] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax", "scale"};
    const auto in = [&](const auto& names) {
        return std::find(std::begin(names), std::end(names), attribute) != std::end(names);
    };
    if (type == "MechanicalObject") return in(kMechanicalObject);
    if (type == "RegularGridTopology" || type == "RegularGrid") return in(kRegularGrid);
    return false;
}

void read_prefixes(io::SceneNode& node, bool fix, std::vector<std::string>& notes) {
    for (auto& c : node.components) {
        const ComponentSpec* spec = find_component(c->type);
        if (spec == nullptr) continue;
        for (io::SceneAttribute& a : c->attributes) {
            const AttributeSpec* s = declared(*spec, a.name);
            if (s == nullptr || s->kind != AttributeKind::real || a.value.empty() || a.value.front() == '@') continue;
            if (read_in_parse(c->type, a.name)) continue;
            std::string_view text = a.value;
            while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front())) != 0) text.remove_prefix(1);
            while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())) != 0) text.remove_suffix(1);
            if (io::detail::parse_double(text)) continue;  // a number: nothing to do
            const std::size_t n = number_prefix(text);
            if (n == 0 || fix) continue;  // not a number at all, or the fix: the builder's error
            const std::string read(text.substr(0, n));
            std::string note = c->file + ":";
            note += std::to_string(a.line);
            note += ": " + c->describe() + ": attribute '" + a.name + "' = '" + a.value + "' read as " + read;
            note +=
                ", as SOFA's Data<T>::read does (it ignores the text after a number; --fix-sofa-quirk "
                "number_trailing_text makes it an error)";
            notes.push_back(std::move(note));
            a.value = read;
        }
    }
    for (auto& child : node.children) read_prefixes(*child, fix, notes);
}

}  // namespace

std::vector<std::string> read_number_prefixes(io::SceneFile& scene, const SofaQuirkFixes& fixes) {
    std::vector<std::string> notes;
    if (scene.root) read_prefixes(*scene.root, fixes.fix_number_trailing_text, notes);
    return notes;
}

}  // namespace penalty::scene
