#include "marionette/core/allocator.hpp"

#include <algorithm>
#include <atomic>
#include <string>

#include "marionette/core/diagnostic.hpp"

namespace marionette {
namespace {

// Written only by setAllocator, which the header says runs before other threads use the
// library; read by every allocation. Atomics all the same, so that a misuse is a wrong
// result, not undefined behaviour.
std::atomic<void* (*)(void*, std::size_t, std::size_t)> g_allocate{nullptr};
std::atomic<void (*)(void*, void*, std::size_t, std::size_t)> g_free{nullptr};
std::atomic<void*> g_user{nullptr};
// Blocks out now, under any allocator: setAllocator is refused while it is not 0.
std::atomic<std::size_t> g_held{0};

}  // namespace

bool setAllocator(const RuntimeAllocatorHooks& hooks, Diagnostics& diagnostics) {
  if (!hooks.allocate != !hooks.free) {
    diagnostics.error("", "setAllocator: give both allocate and free, or neither (to restore operator new/delete)");
    return false;
  }
  if (const std::size_t held = g_held.load(std::memory_order_acquire); held != 0) {
    diagnostics.error("", "setAllocator: the runtime still holds " + std::to_string(held) +
                              " block(s) from the current allocator (a Scene, Character or C handle is alive, or was "
                              "destroyed too recently); set the allocator before making the first runtime object, "
                              "or after destroying the last");
    return false;
  }
  g_user.store(hooks.user, std::memory_order_relaxed);
  g_free.store(hooks.free, std::memory_order_relaxed);
  g_allocate.store(hooks.allocate, std::memory_order_release);
  return true;
}

RuntimeAllocatorHooks currentAllocator() noexcept {
  return {g_allocate.load(std::memory_order_acquire), g_free.load(std::memory_order_relaxed),
          g_user.load(std::memory_order_relaxed)};
}

std::size_t runtimeBlocksHeld() noexcept { return g_held.load(std::memory_order_relaxed); }

void* runtimeAllocate(std::size_t size, std::size_t alignment) {
  alignment = std::max(alignment, kRuntimeMinAlignment);
  size = std::max<std::size_t>(size, 1);
  void* block = nullptr;
  if (auto* allocate = g_allocate.load(std::memory_order_acquire)) {
    block = allocate(g_user.load(std::memory_order_relaxed), size, alignment);
    if (!block) throw std::bad_alloc();
  } else if (alignment > __STDCPP_DEFAULT_NEW_ALIGNMENT__) {
    block = ::operator new(size, std::align_val_t(alignment));
  } else {
    block = ::operator new(size);  // as std::allocator: the same heap, counted by the same tests
  }
  g_held.fetch_add(1, std::memory_order_relaxed);
  return block;
}

void runtimeFree(void* block, std::size_t size, std::size_t alignment) noexcept {
  if (!block) return;
  alignment = std::max(alignment, kRuntimeMinAlignment);
  size = std::max<std::size_t>(size, 1);
  g_held.fetch_sub(1, std::memory_order_relaxed);
  if (auto* free = g_free.load(std::memory_order_acquire)) {
    free(g_user.load(std::memory_order_relaxed), block, size, alignment);
  } else if (alignment > __STDCPP_DEFAULT_NEW_ALIGNMENT__) {
    ::operator delete(block, std::align_val_t(alignment));  // unsized: clang needs -fsized-deallocation for the sized ones
  } else {
    ::operator delete(block);
  }
}

}  // namespace marionette
