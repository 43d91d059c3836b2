#pragma once
// Hand-made Collada documents for tests: the readers' fixtures, written in the test.

#include <string>

namespace plantnbv {
namespace test {

/// A <geometry> with attributes `attributes` (at least its id) holding one triangle of
/// the nine numbers `points`; its <triangles> use material symbol `material` if given.
inline std::string
colladaTriangleGeometry(const std::string& attributes = "id=\"tri\"",
                        const std::string& points = "0 0 0  1 0 0  0 2 0",
                        const std::string& material = "")
{
  return "<geometry " + attributes + R"(><mesh>
      <source id="p"><float_array id="pa" count="9">)" +
         points + R"(</float_array>
        <technique_common><accessor source="#pa" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
      <triangles count="1")" +
         (material.empty() ? "" : " material=\"" + material + "\"") +
         R"(><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>)";
}

/// A Collada 1.4.1 document: `asset` in <asset>, `geometries` in <library_geometries>,
/// then `libraries` (other library_* elements) and the one visual scene's content.
inline std::string colladaDocument(const std::string& asset,
                                   const std::string& geometries,
                                   const std::string& libraries, const std::string& scene)
{
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset>)" +
         asset + "</asset>\n  <library_geometries>\n    " + geometries +
         "\n  </library_geometries>\n  " + libraries +
         R"(
  <library_visual_scenes><visual_scene id="s">)" +
         scene + R"(</visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)";
}

} // namespace test
} // namespace plantnbv
