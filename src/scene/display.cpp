#include "scene/display.hpp"

#include <cstdio>

namespace penalty::scene::display {

std::string number(double value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", value);
    return buf;
}

std::string vector(const Vec3& v) {
    std::string out = "(";
    out += number(v.x());
    out += ", ";
    out += number(v.y());
    out += ", ";
    out += number(v.z());
    out += ")";
    return out;
}

std::string node_path(const Node& node) {
    if (node.parent() == nullptr) return "/";
    std::string out;
    for (const Node* x = &node; x->parent() != nullptr; x = x->parent()) out.insert(0, "/" + x->name());
    return out;
}

std::string node_path(const io::SceneNode& node) { return node.parent ? node.path() : std::string("/"); }

}  // namespace penalty::scene::display
