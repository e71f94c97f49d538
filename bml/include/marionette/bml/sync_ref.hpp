// BML 1.0 sync references, as in start="h2:start-2" or <sync ref="bml1:speech1:s1+0.5"/>:
//   NUMBER                          seconds from the block's start
//   [block:]behavior:syncPoint[:N]  a sync point, optionally of another block and of the
//                                   N-th repetition (1-based; 0 = not given)
//   ... followed by any chain of +NUMBER / -NUMBER offsets (summed)
#pragma once
#include <optional>
#include <string>
#include <string_view>

namespace marionette::bml {

struct SyncRef {
  bool absolute = false;  // a plain time: `offset` seconds from the block's start
  std::string block;      // empty = this block
  std::string behavior;
  std::string syncPoint;  // as written (case is normalized by the scheduler)
  int repetition = 0;     // 0 = not given
  double offset = 0.0;    // seconds, the sum of the +/- chain (or the absolute time)

  [[nodiscard]] std::string toString() const;
};

struct SyncRefParse {
  std::optional<SyncRef> ref;
  std::string error;   // what is wrong, when !ref
  int errorColumn = 0; // 0-based position in the text of the problem
};

[[nodiscard]] SyncRefParse parseSyncRef(std::string_view text);

}  // namespace marionette::bml
