// A BehaviorRequest in one expression, for tests that send behaviors without BML.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "marionette/behavior/behavior_request.hpp"

namespace marionette::test {

inline BehaviorRequest request(std::string id, BehaviorKind kind, BehaviorParameters parameters,
                               std::vector<BehaviorSync> syncs) {
  BehaviorRequest r;
  r.id = std::move(id);
  r.kind = kind;
  r.parameters = std::move(parameters);
  r.syncs = std::move(syncs);
  return r;
}

}  // namespace marionette::test
