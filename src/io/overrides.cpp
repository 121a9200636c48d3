#include "penalty/io/overrides.hpp"

#include <cctype>

namespace penalty::io {

namespace {

bool valid_attribute_name(std::string_view a) {
    if (a.empty()) return false;
    for (const char ch : a) {
        const auto c = static_cast<unsigned char>(ch);
        if (std::isalnum(c) == 0 && ch != '_' && ch != '-' && ch != ':') return false;
    }
    return true;
}

std::vector<std::string> split_path(std::string_view path) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= path.size()) {
        const std::size_t end = path.find('/', start);
        const std::string_view seg = path.substr(start, end == std::string_view::npos ? path.npos : end - start);
        if (!seg.empty()) out.emplace_back(seg);
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
    return out;
}

std::string names_below(const SceneNode& node) {
    std::string out;
    for (const auto& c : node.children) out += (out.empty() ? "" : ", ") + c->name + "/";
    for (const auto& c : node.components)
        if (!c->name.empty()) out += (out.empty() ? "" : ", ") + c->name;
    return out.empty() ? "nothing named" : out;
}

SceneNode* child_node(SceneNode& node, std::string_view name) {
    for (auto& c : node.children)
        if (c->name == name) return c.get();
    return nullptr;
}

SceneComponent* child_component(SceneNode& node, std::string_view name) {
    for (auto& c : node.components)
        if (c->name == name) return c.get();
    return nullptr;
}

}  // namespace

Override parse_override(std::string_view text) {
    std::string quoted;  // built by appends: GCC 12 warns (-Wrestrict, a false positive) on "'" + string
    quoted.reserve(text.size() + 2);
    quoted.append(1, '\'').append(text).append(1, '\'');
    const std::size_t eq = text.find('=');
    if (eq == std::string_view::npos)
        throw OverrideSyntaxError("--set " + quoted + ": expected PATH.attribute=value (no '=')");
    const std::string_view target = text.substr(0, eq);
    const std::size_t slash = target.rfind('/');
    const std::size_t dot = target.rfind('.');
    if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash))
        throw OverrideSyntaxError("--set " + quoted + ": expected PATH.attribute=value (no '.attribute' before '=')");
    Override o;
    o.path = std::string(target.substr(0, dot));
    o.attribute = std::string(target.substr(dot + 1));
    o.value = std::string(text.substr(eq + 1));
    o.text = std::string(text);
    if (!valid_attribute_name(o.attribute))
        throw OverrideSyntaxError("--set " + quoted + ": '" + o.attribute + "' is not an attribute name");
    if (o.path.empty()) o.path.assign(1, '/');
    return o;
}

SceneElement* find_element(SceneFile& file, std::string_view path, std::string* why) {
    if (!file.root) {
        if (why != nullptr) *why = "the scene has no root node";
        return nullptr;
    }
    SceneNode& root = *file.root;
    std::vector<std::string> segments = split_path(path);
    // `/root.dt`: the root's own name (SOFA paths leave it out) when nothing below has that name.
    if (!segments.empty() && !root.name.empty() && segments.front() == root.name &&
        child_node(root, root.name) == nullptr && child_component(root, root.name) == nullptr)
        segments.erase(segments.begin());
    SceneNode* node = &root;
    for (std::size_t i = 0; i < segments.size(); ++i) {
        const std::string& s = segments[i];
        if (SceneNode* next = child_node(*node, s)) {
            node = next;
            continue;
        }
        if (i + 1 == segments.size()) {
            if (SceneComponent* c = child_component(*node, s)) return c;
        }
        if (why != nullptr)
            *why = "no " + std::string(i + 1 == segments.size() ? "node or component" : "node") + " '" + s + "' in '" +
                   node->path() + "' (it has: " + names_below(*node) + ")";
        return nullptr;
    }
    return node;
}

namespace {

/// An override whose path names no element of the scene.
[[noreturn]] void throw_unmatched(const std::string& label, const Override& o, const std::string& why) {
    throw SceneError(label + ": --set '" + o.text + "': " + why);
}

}  // namespace

void apply_overrides(SceneFile& file, const std::vector<Override>& overrides, const AttributeFilter& may_add,
                     const std::function<std::string(const SceneElement&)>& known_attributes) {
    const std::string label = file.root ? file.root->file : file.path.string();
    for (const Override& o : overrides) {
        std::string why;
        SceneElement* e = find_element(file, o.path, &why);
        if (e == nullptr) throw_unmatched(label, o, why);
        if (o.attribute == "name")
            throw_element_error(*e, "--set '" + o.text + "': the name cannot be overridden (paths use it)");
        if (o.attribute == "template") {
            if (e->type == "Node") throw_element_error(*e, "--set '" + o.text + "': a node has no template");
            static_cast<SceneComponent*>(e)->template_name = o.value;
            continue;
        }
        bool found = false;
        for (SceneAttribute& a : e->attributes) {
            if (a.name == o.attribute) {
                a.value = o.value;
                found = true;
            }
        }
        if (found) continue;
        if (!may_add || !may_add(*e, o.attribute)) {
            std::string msg = "--set '" + o.text + "': no attribute '" + o.attribute + "' in the file";
            if (may_add) {
                msg += ", and penalty does not read it for " + e->type;
                if (known_attributes) msg += " (" + known_attributes(*e) + ")";
            }
            throw_element_error(*e, msg);
        }
        e->attributes.push_back(SceneAttribute{o.attribute, o.value, e->line});
    }
}

}  // namespace penalty::io
