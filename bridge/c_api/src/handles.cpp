// The C API's registry of live handles (handles.hpp): every entry point asks it, so a
// destroyed or foreign handle is refused instead of used.
#include <deque>
#include <mutex>
#include <unordered_set>

#include "handles.hpp"

namespace marionette::capi {
namespace {

struct HandleRegistry {
  std::mutex mutex;
  std::unordered_set<const void*> live;
  std::deque<void*> quarantine;  // destroyed handles' memory, freed kQuarantine destroys later
};
HandleRegistry& registry() {
  static HandleRegistry* r = new HandleRegistry();  // never destroyed: handles may outlive static destructors
  return *r;
}

}  // namespace

void* allocateHandle(std::size_t bytes) {
  void* handle = ::operator new(bytes);
  HandleRegistry& r = registry();
  try {
    const std::lock_guard lock(r.mutex);
    r.live.insert(handle);
  } catch (...) {
    ::operator delete(handle);
    throw;
  }
  return handle;
}

void freeHandle(void* handle) noexcept {
  if (!handle) return;
  HandleRegistry& r = registry();
  void* expired = nullptr;
  {
    const std::lock_guard lock(r.mutex);
    r.live.erase(handle);
    try {
      r.quarantine.push_back(handle);
    } catch (...) {  // no memory to hold it back: free it now
      expired = handle;
    }
    if (!expired && r.quarantine.size() > kQuarantine) {
      expired = r.quarantine.front();
      r.quarantine.pop_front();
    }
  }
  ::operator delete(expired);
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
