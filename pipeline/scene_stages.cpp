#include "scene_stages.h"

#include "sim/scene_reader.h"

namespace mf {

SceneStages parseSceneStages(const std::string& text, const std::string& sourceName, const std::vector<std::string>& overrides) {
  scene_reading::SceneDocument doc = scene_reading::parseDocument(text, sourceName, overrides);
  SceneStages s;
  s.scene = scene_reading::readSimulation(doc);
  s.surfacing = readSurfacingSettings(doc, s.scene);
  s.render = readRenderSettings(doc, s.scene, s.surfacing);
  for (const MaterialSpec& m : s.render.solidMaterials) s.surfacing.wallThickness.push_back(m.visible ? m.thickness : 0.0);
  scene_reading::finishScene(doc, s.scene);
  return s;
}

SceneStages loadSceneStages(const std::string& pathOrName, const std::vector<std::string>& overrides) {
  const SceneSource source = readSceneSource(pathOrName);
  return parseSceneStages(source.text, source.name, overrides);
}

}  // namespace mf
