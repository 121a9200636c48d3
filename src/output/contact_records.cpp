#include "penalty/output/contact_records.hpp"

#include "penalty/core/error.hpp"
#include "penalty/response/barycentric_penalty_contact.hpp"

namespace penalty::output {

std::vector<ContactRecord> contact_records(const ContactPipeline& pipeline) {
    std::vector<ContactRecord> records;
    records.reserve(pipeline.graph_entries().size());
    for (const ContactGraphEntry& entry : pipeline.graph_entries()) {
        PENALTY_DEMAND(entry.contact != nullptr && entry.point_states[0] != nullptr &&
                       entry.point_states[1] != nullptr);
        records.push_back({entry.contact->model1().name() + "-" + entry.contact->model2().name(),
                           &entry.contact->force_field(), entry.point_states[0], entry.point_states[1]});
    }
    return records;
}

}  // namespace penalty::output
