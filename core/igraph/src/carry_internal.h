#pragma once
// Shared by carry.cpp and carry_file.cpp: which library actions a carry
// graph is made of (a file is stale when they change).
#include <string>
#include <vector>

#include "fray/sim/action_library.h"

namespace fray::igraph::detail {
// The carry-end actions: names starting with `prefix`, not transitions, two samples or more.
std::vector<int> carryActions(const sim::ActionLibrary& lib, const std::string& prefix);
// The action a pair holds with: the first idle one (else the first).
int carryHold(const sim::ActionLibrary& lib, const std::vector<int>& actions);
}  // namespace fray::igraph::detail
