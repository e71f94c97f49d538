// The C API's registry of live handles (handles.hpp): every entry point asks it, so a
// destroyed or foreign handle is refused instead of used.
#include <dlfcn.h>

#include <deque>
#include <filesystem>
#include <mutex>
#include <unordered_set>
#include <utility>

#include "handles.hpp"
#include "marionette/core/allocator.hpp"

namespace marionette::capi {
namespace {

struct HandleRegistry {
  std::mutex mutex;
  std::unordered_set<const void*> live;
  std::deque<std::pair<void*, std::size_t>> quarantine;  // destroyed handles' memory and size, freed kQuarantine destroys later
};
HandleRegistry& registry() {
  static HandleRegistry* r = new HandleRegistry();  // never destroyed: handles may outlive static destructors
  return *r;
}

}  // namespace

std::string libraryFolder() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&mn_version), &info) == 0 || !info.dli_fname) return {};
  std::error_code ec;
  const std::filesystem::path lib = std::filesystem::absolute(info.dli_fname, ec);
  return ec ? std::string() : lib.parent_path().string();
}

void* allocateHandle(std::size_t bytes) {
  void* handle = runtimeAllocate(bytes);
  HandleRegistry& r = registry();
  try {
    const std::lock_guard lock(r.mutex);
    r.live.insert(handle);
  } catch (...) {
    runtimeFree(handle, bytes);
    throw;
  }
  return handle;
}

void freeHandle(void* handle, std::size_t bytes) noexcept {
  if (!handle) return;
  HandleRegistry& r = registry();
  std::pair<void*, std::size_t> expired{nullptr, 0};
  {
    const std::lock_guard lock(r.mutex);
    r.live.erase(handle);
    try {
      r.quarantine.emplace_back(handle, bytes);
    } catch (...) {  // no memory to hold it back: free it now
      expired = {handle, bytes};
    }
    if (!expired.first && r.quarantine.size() > kQuarantine) {
      expired = r.quarantine.front();
      r.quarantine.pop_front();
    }
  }
  runtimeFree(expired.first, expired.second);
}

std::size_t releaseQuarantineIfNoneLive() noexcept {
  HandleRegistry& r = registry();
  const std::lock_guard lock(r.mutex);
  if (!r.live.empty()) return r.live.size();
  for (const auto& [block, bytes] : r.quarantine) runtimeFree(block, bytes);
  r.quarantine.clear();
  return 0;
}

const char* notLive(const void* handle) noexcept {
  return handle ? " is not a live handle (destroyed, or not from this library)" : " is NULL";
}

std::string badStructSize(const char* call, const char* type, std::size_t given, std::size_t expected) {
  return std::string(call) + ": options->struct_size is " + std::to_string(given) + ", but this library's " + type +
         " is " + std::to_string(expected) + " bytes (start from " + type + "_default(), which sets it)";
}

bool isLive(const void* handle) noexcept {
  if (!handle) return false;
  HandleRegistry& r = registry();
  const std::lock_guard lock(r.mutex);
  return r.live.count(handle) != 0;
}

}  // namespace marionette::capi
