// The C API's engine hooks (marionette.h): a scene's parallel-for on the engine's job
// system, and the engine's heap for the runtime. Both hand the engine's functions to the
// C++ runtime as they are (Scene::setParallelFor, marionette::setAllocator).
#include <string>
#include <type_traits>

#include "handles.hpp"
#include "marionette/core/allocator.hpp"
#include "marionette/core/diagnostic.hpp"

using marionette::capi::fail;
using marionette::capi::guarded;
using marionette::capi::isLive;
using marionette::capi::notLive;

// The C types are the C++ ones (function types do not differ by language linkage in the
// compilers this builds with); a compiler that made them differ stops here.
static_assert(std::is_same_v<mn_parallel_for_fn, marionette::Scene::ParallelFor>,
              "mn_parallel_for_fn must be Scene::ParallelFor");
static_assert(std::is_same_v<mn_alloc_fn, decltype(marionette::RuntimeAllocatorHooks::allocate)>,
              "mn_alloc_fn must be RuntimeAllocatorHooks::allocate");
static_assert(std::is_same_v<mn_free_fn, decltype(marionette::RuntimeAllocatorHooks::free)>,
              "mn_free_fn must be RuntimeAllocatorHooks::free");

extern "C" {

mn_status mn_scene_set_parallel_for(mn_scene* scene, mn_parallel_for_fn fn, void* user) {
  if (!isLive(scene))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_set_parallel_for: scene") + notLive(scene));
  // From a callback the scene is inside update (or BML): its threads must not change under it.
  if (scene->callDepth > 0)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_set_parallel_for: called from a callback of the same scene");
  return guarded(scene, [&] {
    scene->scene.setParallelFor(fn, fn ? user : nullptr);  // allocates the chunks' scratch
    return MN_OK;
  });
}

mn_status mn_set_allocator(mn_alloc_fn alloc_fn, mn_free_fn free_fn, void* user) {
  if (!alloc_fn != !free_fn)
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT,
                "mn_set_allocator: give both alloc_fn and free_fn, or neither (NULL, NULL restores the default)");
  return guarded(nullptr, [&] {
    if (const std::size_t live = marionette::capi::releaseQuarantineIfNoneLive(); live != 0)
      return fail(nullptr, MN_ERROR_INVALID_ARGUMENT,
                  "mn_set_allocator: " + std::to_string(live) +
                      " handle(s) are alive (scenes, characters, bindings, ...): memory from one allocator would be "
                      "given back to another; call it before the first mn_scene_create, or after destroying every "
                      "handle");
    marionette::Diagnostics why;
    if (!marionette::setAllocator({alloc_fn, free_fn, alloc_fn ? user : nullptr}, why))
      return fail(nullptr, MN_ERROR_INVALID_ARGUMENT,
                  "mn_set_allocator: refused: " + (why.items.empty() ? std::string() : why.items.front().message));
    return MN_OK;
  });
}

}  // extern "C"
