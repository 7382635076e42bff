#include "core/bound.hpp"

#include "core/names.hpp"

namespace keel::core {

namespace {
constexpr NameTable<SearchStatus, 4> kSearchStatusNames{"core::SearchStatus",
                                                        {{
                                                            {SearchStatus::optimal, "optimal"},
                                                            {SearchStatus::unproven, "unproven"},
                                                            {SearchStatus::node_limit, "node_limit"},
                                                            {SearchStatus::time_limit, "time_limit"},
                                                        }}};
}  // namespace

std::string_view to_string(SearchStatus s) { return kSearchStatusNames.name(s); }
SearchStatus search_status_from_string(std::string_view s) { return kSearchStatusNames.parse(s); }

}  // namespace keel::core
