#include "penalty/output/contact_records.hpp"

#include "penalty/core/error.hpp"
#include "penalty/response/barycentric_penalty_contact.hpp"

#include <string_view>

namespace penalty::output {

ContactRecord contact_record(const ContactGraphEntry& entry) {
    PENALTY_DEMAND(entry.contact != nullptr && entry.point_states[0] != nullptr && entry.point_states[1] != nullptr);
    return {entry.contact->model1().name() + "-" + entry.contact->model2().name(), &entry.contact->force_field(),
            entry.point_states[0], entry.point_states[1]};
}

bool is_record_of(const ContactRecord& record, const ContactGraphEntry& entry) {
    PENALTY_DEMAND(entry.contact != nullptr);
    const std::string_view name = record.name;
    const std::string_view first = entry.contact->model1().name(), second = entry.contact->model2().name();
    return record.field == &entry.contact->force_field() && record.state1 == entry.point_states[0] &&
           record.state2 == entry.point_states[1] && name.size() == first.size() + 1 + second.size() &&
           name.starts_with(first) && name[first.size()] == '-' && name.ends_with(second);
}

std::vector<ContactRecord> contact_records(const ContactPipeline& pipeline) {
    std::vector<ContactRecord> records;
    records.reserve(pipeline.graph_entries().size());
    for (const ContactGraphEntry& entry : pipeline.graph_entries()) records.push_back(contact_record(entry));
    return records;
}

}  // namespace penalty::output
