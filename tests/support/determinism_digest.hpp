// Run-to-run determinism across processes. A test that checks run() == run() inside one
// process cannot see what differs between processes: addresses (ASLR), hash seeds, the
// order of pointer-keyed containers, memory left uninitialised. Such a test also hands its
// output to recordDigest(); when MARIONETTE_DIGEST_DIR is set (by
// tests/support/compare_digests.cmake, the ctest entry determinism.two_processes), the
// digest goes to DIR/<Suite.Test>.digest, and that script runs the program twice and
// compares the two files.
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace marionette::test {

// FNV-1a over the values' bytes: equal digests mean bit-identical output.
inline std::uint64_t digestOf(const std::vector<float>& values) {
  std::uint64_t h = 14695981039346656037ull;
  for (float v : values) {
    unsigned char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
  }
  return h;
}

inline void recordDigest(const std::vector<float>& values) {
  const char* dir = std::getenv("MARIONETTE_DIGEST_DIR");
  if (!dir || !*dir) return;
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  ASSERT_NE(info, nullptr);
  const std::string path = std::string(dir) + "/" + info->test_suite_name() + "." + info->name() + ".digest";
  std::ofstream out(path);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(digestOf(values)));
  out << values.size() << " values, FNV-1a " << hex << "\n";
  ASSERT_TRUE(out.good()) << "cannot write " << path;
}

}  // namespace marionette::test
