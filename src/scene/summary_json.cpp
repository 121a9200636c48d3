// The run summary as JSON (`penalty run --summary-json FILE`, and the dict Python's Scene.run
// returns): one object, every field of RunSummary under its own name, plus "text" (what
// `penalty run` prints). Numbers in the shortest form that reads back to the same double.
#include "penalty/output/format.hpp"
#include "penalty/scene/runner.hpp"

#include <cmath>
#include <cstdio>

namespace penalty::scene {

namespace {

void append_string(std::string& out, std::string_view text) {
    out += '"';
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (c == '\n') {
            out += "\\n";
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
            out += buf;
        } else {
            out += c;
        }
    }
    out += '"';
}

class JsonObject {
public:
    explicit JsonObject(std::string& out) : out_(out) { out_ += '{'; }
    void key(std::string_view name) {
        out_ += first_ ? "\n  " : ",\n  ";
        first_ = false;
        append_string(out_, name);
        out_ += ": ";
    }
    void number(std::string_view name, double value) {
        key(name);
        if (std::isfinite(value)) output::append_number(out_, value);
        else out_ += "null";  // JSON has no inf or nan
    }
    void integer(std::string_view name, long long value) {
        key(name);
        out_ += std::to_string(value);
    }
    void boolean(std::string_view name, bool value) {
        key(name);
        out_ += value ? "true" : "false";
    }
    void text(std::string_view name, std::string_view value) {
        key(name);
        append_string(out_, value);
    }
    void strings(std::string_view name, const std::vector<std::string>& values) {
        key(name);
        out_ += '[';
        for (std::size_t i = 0; i < values.size(); ++i) {
            if (i > 0) out_ += ", ";
            append_string(out_, values[i]);
        }
        out_ += ']';
    }
    void close() { out_ += "\n}\n"; }

private:
    std::string& out_;
    bool first_ = true;
};

std::string tunnelling_json(const RunSummary::Tunnelling& t) {
    std::string out;
    JsonObject o(out);
    o.text("mode", t.mode);
    o.integer("crossings", t.crossings);
    o.integer("crossing_steps", t.crossing_steps);
    o.integer("prevented", t.prevented);
    o.integer("undone_solves", t.undone_solves);
    o.integer("extra_solves", t.extra_solves);
    o.integer("deepest_halving", t.deepest_halving);
    o.number("max_depth", t.max_depth);
    o.text("first_crossing", t.first_crossing);
    o.integer("stiffened_contacts", t.stiffened_contacts);
    o.number("max_stiffening", t.max_stiffening);
    o.number("stiffening_energy", t.stiffening_energy);
    o.number("guard_seconds", t.guard_seconds);
    o.close();
    out.pop_back();  // close()'s newline: the object sits inside the summary's
    return out;
}

}  // namespace

std::string summary_json(const RunSummary& s) {
    std::string out;
    JsonObject o(out);
    o.integer("steps", s.steps);
    o.number("dt", s.dt);
    o.number("simulated_time", s.simulated_time);
    o.number("wall_seconds", s.wall_seconds);
    o.number("detection_seconds", s.detection_seconds);
    o.number("response_seconds", s.response_seconds);
    o.number("solve_seconds", s.solve_seconds);
    o.number("output_seconds", s.output_seconds);
    o.number("mean_contacts", s.mean_contacts);
    o.integer("max_contacts", static_cast<long long>(s.max_contacts));
    o.number("max_penetration", s.max_penetration);
    o.number("kinetic_energy", s.kinetic_energy);
    o.number("contact_energy", s.contact_energy);
    o.number("dissipated_energy", s.dissipated_energy);
    o.boolean("cg", s.cg);
    o.number("mean_cg_iterations", s.mean_cg_iterations);
    o.integer("max_cg_iterations", s.max_cg_iterations);
    o.integer("cg_limit_steps", s.cg_limit_steps);
    o.boolean("newton", s.newton);
    o.number("mean_newton_iterations", s.mean_newton_iterations);
    o.integer("max_newton_iterations", s.max_newton_iterations);
    o.integer("newton_unconverged_steps", s.newton_unconverged_steps);
    std::vector<std::string> files;
    for (const auto& f : s.state_files) files.push_back(f.string());
    o.strings("state_files", files);
    o.key("tunnelling");  // the guard's totals (docs/no-tunnelling.md), null without a guard
    if (s.tunnelling.mode.empty()) out += "null";
    else out += tunnelling_json(s.tunnelling);
    o.text("text", format_summary(s));
    o.close();
    return out;
}

}  // namespace penalty::scene
