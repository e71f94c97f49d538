// The runtime allocator: an engine's own heap for the runtime's objects and their
// per-character buffers (as ozz's memory::Allocator, Jolt's JPH::Allocate, ACL's
// iallocator). By default it is operator new/delete, exactly what std::allocator does.
//
// What goes through it (docs/architecture.md, Memory, keeps the full list): Scene and
// Character objects, a character's private state, its pose, layer and pass buffers, its
// TransformBuffer's arrays, the scenes' per-frame blend scratch and worker/chunk scratch,
// and the C API's handles. What does not: assets and their import, rigs and their clips,
// names (std::string), behavior timelines and controllers, the BML realizer, the speech
// service, std::thread's own state and third-party libraries (they use operator new).
//
// The rule: setAllocator may be called only while the runtime holds no memory it got
// from the runtime allocator (the current one, the default included), i.e. before the
// first Scene or Character is made or after the last is destroyed. Memory is always
// given back to the allocator that gave it; a change while blocks are held would hand
// one allocator another's memory, so it is refused. Not thread-safe against other
// library calls: install it at start-up, before other threads use the library.
#pragma once
#include <cstddef>
#include <limits>
#include <new>
#include <type_traits>
#include <vector>

namespace marionette {

struct Diagnostics;

// Alignment the runtime asks for at least (operator new's): an engine's allocate sees
// alignment >= this, a power of two.
inline constexpr std::size_t kRuntimeMinAlignment = __STDCPP_DEFAULT_NEW_ALIGNMENT__;

// An engine's allocator. `allocate` returns a block of `size` bytes (> 0) aligned to
// `alignment`, or null when out of memory (the runtime call then fails as with
// std::bad_alloc; the C API returns MN_ERROR_OUT_OF_MEMORY). `free` gets back exactly
// the block, size and alignment that allocate returned/was asked for. Both may be called
// from any thread that calls the library, concurrently (two scenes on two threads), and
// never from inside Scene::update after warm-up.
struct RuntimeAllocatorHooks {
  void* (*allocate)(void* user, std::size_t size, std::size_t alignment) = nullptr;
  void (*free)(void* user, void* block, std::size_t size, std::size_t alignment) = nullptr;
  void* user = nullptr;
};

// Installs `hooks` (both functions, or neither to restore operator new/delete). Returns
// false, with a diagnostic saying why, when only one function is given or while the
// runtime holds memory from the current allocator (the rule above).
[[nodiscard]] bool setAllocator(const RuntimeAllocatorHooks& hooks, Diagnostics& diagnostics);
// The hooks in use (null functions: the default).
[[nodiscard]] RuntimeAllocatorHooks currentAllocator() noexcept;
// Blocks the runtime holds from the runtime allocator now (whichever installed them).
[[nodiscard]] std::size_t runtimeBlocksHeld() noexcept;

// Through the installed allocator; throws std::bad_alloc when it returns null.
// `alignment` is raised to kRuntimeMinAlignment.
[[nodiscard]] void* runtimeAllocate(std::size_t size, std::size_t alignment = kRuntimeMinAlignment);
void runtimeFree(void* block, std::size_t size, std::size_t alignment = kRuntimeMinAlignment) noexcept;

// A std allocator over the runtime allocator, for the runtime's vectors.
template <class T>
class RuntimeAllocator {
 public:
  using value_type = T;
  using is_always_equal = std::true_type;
  RuntimeAllocator() noexcept = default;
  template <class U>
  RuntimeAllocator(const RuntimeAllocator<U>&) noexcept {}  // NOLINT: implicit, as allocators rebind

  [[nodiscard]] T* allocate(std::size_t n) {
    if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(runtimeAllocate(n * sizeof(T), alignof(T)));
  }
  void deallocate(T* p, std::size_t n) noexcept { runtimeFree(p, n * sizeof(T), alignof(T)); }

  template <class U>
  friend bool operator==(const RuntimeAllocator&, const RuntimeAllocator<U>&) noexcept {
    return true;
  }
};

template <class T>
using RuntimeVector = std::vector<T, RuntimeAllocator<T>>;

// A base whose class-level operator new/delete go through the runtime allocator: `new T`,
// std::make_unique<T> and delete of a T use it (std::make_shared does not: it calls
// ::operator new; use std::allocate_shared with RuntimeAllocator).
struct RuntimeAllocated {
  static void* operator new(std::size_t size) { return runtimeAllocate(size); }
  static void* operator new(std::size_t size, std::align_val_t a) {
    return runtimeAllocate(size, static_cast<std::size_t>(a));
  }
  static void operator delete(void* p, std::size_t size) noexcept { runtimeFree(p, size); }
  static void operator delete(void* p, std::size_t size, std::align_val_t a) noexcept {
    runtimeFree(p, size, static_cast<std::size_t>(a));
  }
  // Placement new stays available (a class operator new hides the global ones).
  static void* operator new(std::size_t, void* where) noexcept { return where; }
  static void operator delete(void*, void*) noexcept {}
};

}  // namespace marionette
