#include "scene_catalogue.hpp"

#include <cmath>
#include <limits>

#include "marionette/prt/transfer_mesh.hpp"

namespace marionette::ar {

std::vector<CatalogueEntry> sceneCatalogue(const Scene& scene, const SceneLoadResult& loaded, Diagnostics& diagnostics) {
  std::vector<CatalogueEntry> out;
  for (const auto& c : scene.characters()) {
    const std::shared_ptr<const Asset> asset = loaded.assetOf(c->name());
    const std::string& file = c->rig().sourcePath();
    std::vector<glm::vec3> points;
    if (asset) {
      Diagnostics meshDiagnostics;  // the renderer reports the mesh's problems when it draws it
      points = prt::bindPoseMesh(*asset, meshDiagnostics).positions;
    }
    if (points.empty()) {
      diagnostics.warning(file, "character '" + c->name() + "' has no mesh: measured by its joints");
      for (const glm::mat4& m : c->rig().skeleton().restModelMatrices()) points.emplace_back(m[3]);
    }
    const glm::mat4 world = c->worldMatrix();
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const glm::vec3& p : points) {
      const glm::vec3 w(world * glm::vec4(p, 1.0f));
      if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z)) continue;
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
    CatalogueEntry e;
    e.name = c->name();
    e.asset = file;
    if (hi.y > lo.y) {
      e.heightMetres = hi.y - lo.y;
      e.pivot = glm::vec3(0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z));
    } else {
      diagnostics.warning(file, "character '" + c->name() + "' has no height: taken as 1 m");
    }
    e.profileLifeHeight = c->rig().profile().lifeHeight;
    if (const LifeSize life = e.lifeSize(); !life.note.empty())  // placed at the default height: say why
      diagnostics.items.push_back({Severity::Note, file, 0, 0, life.note});
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace marionette::ar
