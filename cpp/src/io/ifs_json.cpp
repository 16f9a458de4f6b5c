#include "ifsforge/io/ifs_json.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/text_file.h"
#include "ifsforge/model/map_params.h"
#include "ifsforge/model/recurrent.h"
#include "ifsforge/model/super_ifs.h"
#include "json_reader.h"
#include "polar_json.h"

namespace ifsforge {
namespace {

using nlohmann::json;

using detail::JsonReader;

/// The rows of the non-spatial channels ("channels": n coefficients then the offset, per
/// channel) into `map`, whose spatial rows are set.
void read_channel_rows(const JsonReader& r, const json& m, const std::string& path, const ChannelLayout& layout,
                       AffineMap& map) {
  const int n = layout.dim(), k = layout.spatial_dims();
  if (n > k) {
    if (!m.contains("channels"))
      r.fail(path, "layout '" + layout.text() + "' needs 'channels': one row of " + std::to_string(n + 1) +
                       " numbers (coefficients, offset) per channel after the spatial ones");
    const json& rows = m["channels"];
    if (!rows.is_array() || rows.size() != static_cast<std::size_t>(n - k))
      r.fail(path + "/channels", "expected " + std::to_string(n - k) + " rows");
    for (int i = k; i < n; ++i) {
      auto row = r.coefficients(rows[i - k], path + "/channels/" + std::to_string(i - k), n + 1);
      for (int j = 0; j < n; ++j) map.a(i, j) = row[j];
      map.b(i) = row[n];
    }
  } else if (m.contains("channels")) {
    r.fail(path + "/channels", "layout '" + layout.text() + "' has no extra channels");
  }
}

/// One map of "maps": affine, or polar (3.3.3), whose AffineMap is its shadow and is
/// returned with the polar map in `polar`.
AffineMap read_map(const JsonReader& r, const json& m, const std::string& path, const ChannelLayout& layout,
                   std::optional<PolarMap>& polar) {
  if (!m.is_object()) r.fail(path, "a map must be an object, found " + JsonReader::describe(m));
  const int n = layout.dim(), k = layout.spatial_dims();
  if (m.contains("polar")) {
    r.only(m, path, {"polar", "probability", "channels", "name"}, "a polar map has polar, probability, channels");
    if (k != 2) r.fail(path + "/polar", "polar maps are maps of the plane; layout '" + layout.text() + "' is not 2D");
    polar = detail::read_polar_map(r, m["polar"], path + "/polar");
    AffineMap channels(n);
    read_channel_rows(r, m, path, layout, channels);
    return polar->shadow(channels);
  }
  static const char* kParamKeys[] = {"scale", "rotation", "shear", "reflect", "translation"};
  bool has_params = false;
  for (const char* key : kParamKeys) has_params |= m.contains(key);
  r.only(m, path, {"matrix", "offset", "probability", "channels", "scale", "rotation", "shear", "reflect", "translation", "name"},
         "a map has matrix + offset, or scale, rotation, shear, reflect, translation, or is {\"polar\": ...}");
  if (m.contains("matrix")) {
    if (has_params) r.fail(path, "give either matrix + offset or parameters, not both");
    const json& rows = m["matrix"];
    if (!rows.is_array() || rows.size() != static_cast<std::size_t>(n))
      r.fail(path + "/matrix", "expected " + std::to_string(n) + " rows for layout '" + layout.text() + "'");
    std::vector<double> a;
    for (int i = 0; i < n; ++i) {
      auto row = r.coefficients(rows[i], path + "/matrix/" + std::to_string(i), n);
      a.insert(a.end(), row.begin(), row.end());
    }
    if (!m.contains("offset")) r.fail(path, "a matrix needs an offset");
    return AffineMap(n, a, r.coefficients(m["offset"], path + "/offset", n));
  }
  if (!has_params) r.fail(path, "a map needs a matrix and offset, or parameters (scale, rotation, ...)");
  MapParams p;
  p.dim = k;
  if (m.contains("scale")) {
    auto s = r.per_axis(m["scale"], path + "/scale", k);
    std::copy(s.begin(), s.end(), p.scale.begin());
  }
  if (m.contains("rotation")) {
    if (k == 2 && m["rotation"].is_number()) {
      p.rotation[0] = p.rotation[1] = r.number(m["rotation"], path + "/rotation");
    } else {
      auto s = r.numbers(m["rotation"], path + "/rotation", k);
      std::copy(s.begin(), s.end(), p.rotation.begin());
    }
  }
  if (m.contains("shear")) {
    if (k == 2) {
      p.shear[0] = r.number(m["shear"], path + "/shear");
    } else {
      auto s = r.numbers(m["shear"], path + "/shear", 3);
      std::copy(s.begin(), s.end(), p.shear.begin());
    }
  }
  if (m.contains("reflect")) {
    const json& f = m["reflect"];
    if (!f.is_array() || f.size() != static_cast<std::size_t>(k))
      r.fail(path + "/reflect", "expected " + std::to_string(k) + " booleans");
    for (int i = 0; i < k; ++i) {
      if (!f[i].is_boolean()) r.fail(path + "/reflect/" + std::to_string(i), "expected true or false");
      p.reflect[i] = f[i].get<bool>();
    }
  }
  if (m.contains("translation")) {
    auto t = r.coefficients(m["translation"], path + "/translation", k);
    std::copy(t.begin(), t.end(), p.translation.begin());
  }
  const AffineMap spatial = map_from_params(p);
  AffineMap map(n);
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) map.a(i, j) = spatial.a(i, j);
    map.b(i) = spatial.b(i);
  }
  read_channel_rows(r, m, path, layout, map);
  return map;
}


/// The maps of one system (`obj` holds "maps" and maybe "probabilities"), as an Ifs. A
/// recurrent system takes its map frequencies from its transitions, so its maps carry none.
Ifs read_maps(const JsonReader& r, const json& obj, const std::string& at, const ChannelLayout& layout,
              const std::string& name, const std::string& source, bool recurrent) {
  if (!obj.contains("maps") || !obj["maps"].is_array() || obj["maps"].empty())
    r.fail(at + "/maps", "expected a non-empty array of maps");
  std::vector<AffineMap> maps;
  std::vector<std::optional<PolarMap>> polar;
  std::vector<double> probabilities;
  std::size_t with_probability = 0;
  const json& list = obj["maps"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string path = at + "/maps/" + std::to_string(i);
    polar.emplace_back();
    maps.push_back(read_map(r, list[i], path, layout, polar.back()));
    if (list[i].contains("probability")) {
      if (recurrent)
        r.fail(path + "/probability", "a recurrent system's map frequencies come from its transitions; remove it");
      ++with_probability;
      const double p = r.number(list[i]["probability"], path + "/probability");
      if (p < 0) r.fail(path + "/probability", "a probability must be 0 or more, found " + JsonReader::describe(list[i]["probability"]));
      probabilities.push_back(p);
    }
  }
  if (with_probability != 0 && with_probability != maps.size())
    r.fail(at + "/maps", "either every map has a probability or none does");
  if (with_probability == 0) {
    const std::string rule = obj.contains("probabilities") ? r.text(obj["probabilities"], at + "/probabilities") : "jacobian";
    if (rule == "uniform")
      probabilities.assign(maps.size(), 1.0);
    else if (rule != "jacobian")
      r.fail(at + "/probabilities", "expected \"uniform\" or \"jacobian\"");
  } else if (obj.contains("probabilities")) {
    r.fail(at + "/probabilities", "the maps already give their probabilities");
  }
  try {
    Ifs ifs(name, layout, maps, probabilities);
    ifs.set_polar_maps(std::move(polar));
    return ifs;
  } catch (const InputError& e) {
    throw InputError(source + ": " + (at.empty() ? "" : at + ": ") + e.what());
  }
}

/// "systems": [{"name", "probability", "maps", "probabilities"}...] and "variability" (3.3.5).
Ifs read_super_ifs(const JsonReader& r, const json& doc, const ChannelLayout& layout, const std::string& name,
                   const std::string& source) {
  if (doc.contains("maps")) r.fail("/maps", "a super IFS lists its maps inside \"systems\"");
  if (doc.contains("probabilities")) r.fail("/probabilities", "a super IFS gives probabilities per member system");
  if (doc.contains("transitions")) r.fail("/transitions", "a super IFS cannot be recurrent");
  const json& list = doc["systems"];
  if (!list.is_array() || list.empty()) r.fail("/systems", "expected a non-empty array of member systems");
  std::vector<Ifs> members;
  std::vector<double> probabilities;
  for (std::size_t n = 0; n < list.size(); ++n) {
    const std::string at = "/systems/" + std::to_string(n);
    const json& member = list[n];
    if (!member.is_object()) r.fail(at, "a member system must be an object");
    r.only(member, at, {"name", "probability", "maps", "probabilities"},
           "a member has name, probability, maps, probabilities");
    const std::string member_name =
        member.contains("name") ? r.text(member["name"], at + "/name") : "member " + std::to_string(n + 1);
    members.push_back(read_maps(r, member, at, layout, member_name, source, false));
    probabilities.push_back(member.contains("probability") ? r.number(member["probability"], at + "/probability") : 1.0);
  }
  int variability = 2;
  if (doc.contains("variability")) {
    const double v = r.number(doc["variability"], "/variability");
    if (v != std::floor(v) || v < 1 || v > 64) r.fail("/variability", "expected a whole number V in 1..64");
    variability = static_cast<int>(v);
  }
  return r.at("/systems", [&] { return make_super_ifs(name, members, probabilities, variability); });
}

Condensation::Path read_path(const JsonReader& r, const json& j, const std::string& path) {
  if (!j.is_array()) r.fail(path, "expected an array of [x, y] points");
  Condensation::Path out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const auto xy = r.numbers(j[i], path + "/" + std::to_string(i), 2);
    out.push_back({xy[0], xy[1]});
  }
  return out;
}

/// "condensation": {"polylines": [[[x, y], ...]], "polygons": [...], "channels": [...], "probability": p0}
Condensation read_condensation(const JsonReader& r, const json& j, int channels) {
  if (!j.is_object()) r.fail("/condensation", "expected an object with polylines and/or polygons");
  Condensation c;
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string at = "/condensation/" + it.key();
    if (it.key() == "polylines" || it.key() == "polygons") {
      if (!it->is_array()) r.fail(at, "expected an array of paths");
      for (std::size_t i = 0; i < it->size(); ++i)
        (it.key() == "polylines" ? c.polylines : c.polygons).push_back(read_path(r, (*it)[i], at + "/" + std::to_string(i)));
    } else if (it.key() == "channels") {
      c.channels = r.numbers(*it, at, static_cast<std::size_t>(channels));
    } else if (it.key() == "probability") {
      c.probability = r.number(*it, at);
    } else {
      r.fail(at, "unknown field (a condensation set has polylines, polygons, channels, probability)");
    }
  }
  if (c.empty()) r.fail("/condensation", "expected at least one polyline or polygon");
  return c;
}

}  // namespace

Ifs parse_ifs_json(const std::string& text, const std::string& source) {
  const JsonReader r(source);
  const json doc = r.document(text);
  if (!doc.is_object()) r.fail("", "expected a JSON object holding one system");
  if (doc.contains("format") && r.text(doc["format"], "/format") != kFormatVersion)
    r.fail("/format", "unsupported format '" + doc["format"].get<std::string>() + "' (this is " + kFormatVersion + ")");
  r.only(doc, "", {"format", "name", "description", "layout", "maps", "probabilities", "render", "transitions",
                   "condensation", "systems", "variability"});
  ChannelLayout layout("xy");
  if (doc.contains("layout")) layout = r.at("/layout", [&] { return ChannelLayout(r.text(doc["layout"], "/layout")); });
  std::string name = doc.contains("name") ? r.text(doc["name"], "/name") : "untitled";
  Ifs ifs;
  if (doc.contains("systems")) {
    ifs = read_super_ifs(r, doc, layout, name, source);
  } else {
    ifs = read_maps(r, doc, "", layout, name, source, doc.contains("transitions"));
    if (doc.contains("variability")) r.fail("/variability", "only a super IFS (\"systems\") has a variability");
  }
  if (doc.contains("transitions")) {
    const json& rows = doc["transitions"];
    const std::size_t n = ifs.size();
    if (!rows.is_array() || rows.size() != n)
      r.fail("/transitions", "expected " + std::to_string(n) + " rows (one per map) of " + std::to_string(n) + " numbers");
    std::vector<double> values;
    for (std::size_t i = 0; i < n; ++i) {
      auto row = r.numbers(rows[i], "/transitions/" + std::to_string(i), n);
      values.insert(values.end(), row.begin(), row.end());
    }
    r.at("/transitions", [&] { ifs.set_transitions(TransitionMatrix(n, values)); });
  }
  if (doc.contains("condensation"))
    r.at("/condensation", [&] { ifs.set_condensation(read_condensation(r, doc["condensation"], ifs.dim() - ifs.spatial_dims())); });
  if (doc.contains("description")) ifs.set_description(r.text(doc["description"], "/description"));
  if (doc.contains("render")) {
    const json& j = doc["render"];
    if (!j.is_object()) r.fail("/render", "expected an object");
    RenderDefaults d;
    if (j.contains("window") && !j["window"].is_null()) {
      d.window = r.numbers(j["window"], "/render/window", 4);
      if (!(d.window[2] > d.window[0] && d.window[3] > d.window[1]))
        r.fail("/render/window", "expected xmin ymin xmax ymax with xmin < xmax and ymin < ymax");
    }
    if (j.contains("view")) {
      const json& v = j["view"];
      if (!v.is_object()) r.fail("/render/view", "expected {\"yaw\": degrees, \"pitch\": degrees}");
      d.view = {v.contains("yaw") ? r.number(v["yaw"], "/render/view/yaw") : 0.0,
                v.contains("pitch") ? r.number(v["pitch"], "/render/view/pitch") : 0.0};
    }
    if (j.contains("algorithm")) d.algorithm = r.text(j["algorithm"], "/render/algorithm");
    if (j.contains("size")) {
      const auto size = r.per_axis(j["size"], "/render/size", 2);
      if (size[0] < 1 || size[1] < 1 || size[0] > 65535 || size[1] > 65535)
        r.fail("/render/size", "expected 1..65535 pixels per side");
      d.width = static_cast<int>(size[0]);
      d.height = static_cast<int>(size[1]);
    }
    ifs.set_render_defaults(d);
  }
  return ifs;
}

Ifs read_ifs_json(const std::string& path) { return parse_ifs_json(read_text_file(path), path); }

std::string to_ifs_json(const Ifs& ifs) {
  const int n = ifs.dim();
  std::ostringstream out;
  out << "{\n  \"format\": \"" << kFormatVersion << "\",\n  \"name\": " << json(ifs.name()).dump() << ",\n";
  if (!ifs.description().empty()) out << "  \"description\": " << json(ifs.description()).dump() << ",\n";
  out << "  \"layout\": " << json(ifs.layout().text()).dump() << ",\n";
  // Maps [first, last) with their probabilities divided by `share` (none for a recurrent system).
  auto write_maps = [&](std::size_t first, std::size_t last, double share, const std::string& indent) {
    out << indent << "\"maps\": [\n";
    for (std::size_t i = first; i < last; ++i) {
      const AffineMap& m = ifs.map(i);
      if (ifs.polar() && ifs.polar_maps()[i]) {
        // The polar map, and its shadow's channel rows as read_channel_rows reads them.
        out << indent << "  {\"polar\": " << detail::polar_map_json(*ifs.polar_maps()[i]).dump();
        json channels = json::array();
        for (int r = ifs.spatial_dims(); r < n; ++r) {
          json row = json::array();
          for (int c = 0; c < n; ++c) row.push_back(m.a(r, c));
          row.push_back(m.b(r));
          channels.push_back(row);
        }
        if (!channels.empty()) out << ", \"channels\": " << channels.dump();
      } else {
        json matrix = json::array();
        for (int r = 0; r < n; ++r) {
          json row = json::array();
          for (int c = 0; c < n; ++c) row.push_back(m.a(r, c));
          matrix.push_back(row);
        }
        out << indent << "  {\"matrix\": " << matrix.dump() << ", \"offset\": " << json(m.offset()).dump();
      }
      if (!ifs.recurrent()) out << ", \"probability\": " << json(ifs.probabilities()[i] / share).dump();
      out << "}" << (i + 1 < last ? ",\n" : "\n");
    }
    out << indent << "]";
  };
  const SuperIfs& parts = ifs.super_ifs();
  if (parts.empty()) {
    write_maps(0, ifs.size(), 1.0, "  ");
  } else {
    out << "  \"variability\": " << parts.variability << ",\n  \"systems\": [\n";
    for (std::size_t k = 0; k < parts.members(); ++k) {
      out << "    {\"name\": " << json(parts.names[k]).dump() << ", \"probability\": "
          << json(parts.probabilities[k]).dump() << ",\n";
      double share = 0.0;
      for (std::size_t i = parts.first_map(k); i < parts.first_map(k) + parts.sizes[k]; ++i) share += ifs.probabilities()[i];
      write_maps(parts.first_map(k), parts.first_map(k) + parts.sizes[k], share, "     ");
      out << "}" << (k + 1 < parts.members() ? ",\n" : "\n");
    }
    out << "  ]";
  }
  if (ifs.recurrent()) {
    json rows = json::array();
    for (std::size_t i = 0; i < ifs.size(); ++i) rows.push_back(ifs.transitions().row(i));
    out << ",\n  \"transitions\": " << rows.dump();
  }
  const Condensation& c = ifs.condensation();
  if (!c.empty()) {
    json j = json::object();
    if (!c.polylines.empty()) j["polylines"] = c.polylines;
    if (!c.polygons.empty()) j["polygons"] = c.polygons;
    if (!c.channels.empty()) j["channels"] = c.channels;
    j["probability"] = c.probability;
    out << ",\n  \"condensation\": " << j.dump();
  }
  const RenderDefaults& d = ifs.render_defaults();
  json render = json::object();
  if (!d.window.empty()) render["window"] = d.window;
  if (!d.view.empty()) render["view"] = {{"yaw", d.view[0]}, {"pitch", d.view[1]}};
  if (!d.algorithm.empty()) render["algorithm"] = d.algorithm;
  if (d.width > 0) render["size"] = {d.width, d.height};
  if (!render.empty()) out << ",\n  \"render\": " << render.dump();
  out << "\n}\n";
  return out.str();
}

void write_ifs_json(const std::string& path, const Ifs& ifs) {
  const std::string text = to_ifs_json(ifs);
  AtomicFile out(path);
  std::fwrite(text.data(), 1, text.size(), out.file());
  out.commit();
}

}  // namespace ifsforge
