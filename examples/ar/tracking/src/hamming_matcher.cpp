#include "hamming_matcher.hpp"

#include <cstring>

namespace marionette::ar {

namespace {

// A descriptor's four 64-bit words, each loaded on its own: a 32-byte copy through the stack
// followed by 8-byte reads of it defeats store forwarding (Tracking/HammingMatch: 2.9 ns a pair
// that way, 1.6 ns this way).
struct Descriptor {
  std::uint64_t w[4];
};

inline std::uint64_t word(const std::uint8_t* p, int i) noexcept {
  std::uint64_t w;
  std::memcpy(&w, p + 8 * i, sizeof w);
  return w;
}

inline Descriptor load(const std::uint8_t* p) noexcept { return {{word(p, 0), word(p, 1), word(p, 2), word(p, 3)}}; }

inline int distance(const Descriptor& a, const std::uint8_t* b) noexcept {
  return __builtin_popcountll(a.w[0] ^ word(b, 0)) + __builtin_popcountll(a.w[1] ^ word(b, 1)) +
         __builtin_popcountll(a.w[2] ^ word(b, 2)) + __builtin_popcountll(a.w[3] ^ word(b, 3));
}

// The search, compiled twice: the x86-64 baseline has no popcount instruction (GCC then counts
// bits in software, 5x slower here), so the POPCNT build is chosen at run time where the CPU
// has it. Both give the same result.
template <int kVariant>
inline void search(const cv::Mat& query, const cv::Mat& train, std::vector<HammingMatch>& out) noexcept {
  for (int q = 0; q < query.rows; ++q) {
    const Descriptor a = load(query.ptr<std::uint8_t>(q));
    int best = 257, second = 257, bestRow = -1;
    for (int t = 0; t < train.rows; ++t) {
      const int d = distance(a, train.ptr<std::uint8_t>(t));
      if (d < best) {
        second = best;
        best = d;
        bestRow = t;
      } else if (d < second) {
        second = d;
      }
    }
    out.push_back({q, bestRow, best, second});
  }
}

void searchBaseline(const cv::Mat& query, const cv::Mat& train, std::vector<HammingMatch>& out) noexcept {
  search<0>(query, train, out);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("popcnt"))) void searchPopcnt(const cv::Mat& query, const cv::Mat& train,
                                                    std::vector<HammingMatch>& out) noexcept {
  search<1>(query, train, out);
}
#endif

}  // namespace

void matchNearestTwo(const cv::Mat& query, const cv::Mat& train, std::vector<HammingMatch>& out) noexcept {
  out.clear();
  if (query.type() != CV_8UC1 || train.type() != CV_8UC1 || query.cols != 32 || train.cols != 32 || train.rows < 1 ||
      out.capacity() < static_cast<std::size_t>(query.rows))
    return;
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool popcnt = __builtin_cpu_supports("popcnt");
  if (popcnt) return searchPopcnt(query, train, out);
#endif
  searchBaseline(query, train, out);
}

}  // namespace marionette::ar
