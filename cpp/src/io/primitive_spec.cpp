#include "ifsforge/io/primitive_spec.h"

#include <memory>
#include <utility>

#include "ifsforge/core/error.h"
#include "ifsforge/io/mesh_reader.h"

namespace ifsforge {

Primitive parse_primitive(const std::string& spec) {
  Primitive p;
  if (spec.rfind("mesh:", 0) == 0) {
    p.shape = Shape::Mesh;
    p.mesh_path = spec.substr(5);
    if (p.mesh_path.empty()) throw InputError("primitive 'mesh:' needs a path, e.g. mesh:leaf.ply");
    p.mesh = std::make_shared<TriangleMesh>(read_mesh(p.mesh_path));
    return p;
  }
  static const std::pair<const char*, Shape> kShapes[] = {
      {"line", Shape::Line}, {"circle", Shape::Circle}, {"triangle", Shape::Triangle}, {"square", Shape::Square},
      {"sphere", Shape::Sphere}, {"box", Shape::Box}, {"cone", Shape::Cone}, {"cylinder", Shape::Cylinder},
      {"torus", Shape::Torus}};
  std::string base = spec;
  const std::string outline = "-outline";
  if (base.size() > outline.size() && base.compare(base.size() - outline.size(), outline.size(), outline) == 0) {
    base.resize(base.size() - outline.size());
    p.outline = true;
  }
  for (const auto& [name, shape] : kShapes)
    if (base == name) {
      p.shape = shape;
      if (p.outline && !(shape == Shape::Circle || shape == Shape::Triangle || shape == Shape::Square)) break;
      return p;
    }
  std::string choices;
  for (const auto& n : builtin_primitive_names()) choices += (choices.empty() ? "" : ", ") + n;
  throw InputError("unknown primitive '" + spec + "': choose " + choices + " or mesh:PATH");
}

std::vector<Primitive> parse_primitives(const std::string& specs) {
  std::vector<Primitive> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = specs.find(',', start);
    std::string item = specs.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    out.push_back(parse_primitive(item));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace ifsforge
