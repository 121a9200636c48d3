// The tunnelling guard from Python (docs/no-tunnelling.md): a scene's mode, its last step's
// report, the run's totals and `penalty info --contact-advice` as data. Scene's bindings
// (scene_bindings.cpp) call these.
#include "bindings.hpp"

#include "penalty/scene/contact_advice.hpp"
#include "penalty/scene/runner.hpp"

#include <pybind11/stl.h>

namespace penalty::python {

std::string tunnelling_mode(const scene::Scene& s) { return tunnelling_mode_name(s.tunnelling_options().mode); }

void set_tunnelling_mode(scene::Scene& s, const std::string& mode) {
    const std::optional<TunnellingMode> m = parse_tunnelling_mode(mode);
    if (!m) throw py::value_error("no_tunnelling: '" + mode + "' is not one of off, warn, substep, stiffen");
    TunnellingOptions o = s.tunnelling_options();
    o.mode = *m;
    s.set_tunnelling(o);
}

py::dict crossing_dict(const Crossing& c) {
    py::dict d;
    d["kind"] = crossing_kind_name(c.kind);
    d["model1"] = c.model1 ? c.model1->name() : std::string();
    d["model2"] = c.model2 ? c.model2->name() : std::string();
    const auto used = [](const std::array<Index, 3>& a) {
        py::list l;
        for (Index i : a)
            if (i >= 0) l.append(i);
        return l;
    };
    d["dofs1"] = used(c.dofs1);
    d["dofs2"] = used(c.dofs2);
    d["element1"] = c.element1;
    d["element2"] = c.element2;
    d["toi"] = c.toi;
    d["depth"] = c.depth;
    d["point"] = py::make_tuple(c.point.x(), c.point.y(), c.point.z());
    d["text"] = c.describe();
    return d;
}

py::object tunnelling_report(const scene::Scene& s) {
    const TunnellingReport* r = s.tunnelling_report();
    if (r == nullptr) return py::none();
    py::dict d;
    py::list crossings;
    for (const Crossing& c : r->crossings) crossings.append(crossing_dict(c));
    d["mode"] = tunnelling_mode(s);
    d["crossings"] = crossings;
    d["prevented"] = r->prevented;
    d["max_depth"] = r->max_depth;
    d["solves"] = r->solves;
    d["undone_solves"] = r->undone_solves;
    d["deepest_halving"] = r->deepest_halving;
    d["stiffened_contacts"] = r->stiffened_contacts;
    d["max_stiffening"] = r->max_stiffening;
    d["stiffening_energy"] = r->stiffening_energy;
    d["guard_seconds"] = r->guard_seconds;
    return d;
}

py::list contact_advice_list(const scene::Scene& s, std::optional<double> impact_speed) {
    py::list out;
    for (const scene::PairAdvice& a : scene::contact_advice_pairs(s, impact_speed)) {
        py::dict d;
        d["model1"] = a.model1;
        d["model2"] = a.model2;
        d["impact_speed"] = a.impact_speed;
        d["mass"] = a.mass;
        d["reach"] = a.reach;
        d["alarm"] = a.alarm;
        d["ks"] = a.ks;
        d["dt"] = a.dt;
        d["max_dt_detection"] = a.max_dt_detection;
        d["min_ks_energy"] = a.min_ks_energy;
        d["min_ks_implicit"] = a.min_ks_implicit;
        d["explicit_contact"] = a.explicit_contact;
        d["max_dt_explicit"] = a.max_dt_explicit;
        d["cg_iterations"] = a.cg_iterations;
        d["cg_limit"] = a.cg_limit;
        d["safe"] = a.safe();
        out.append(d);
    }
    return out;
}

}  // namespace penalty::python
