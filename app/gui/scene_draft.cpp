#include "app/gui/scene_draft.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "core/frame/file_name.h"
#include "core/scene/mesh_generator_keys.h"
#include "core/scene/scene.h"
#include "core/scene/scene_edit.h"
#include "core/scene/schema_text.h"
#include "core/scene/timeline.h"

namespace ff::app::gui {
namespace {

using Fields = std::vector<std::pair<std::string, std::string>>;

std::string quoted(const std::string& s) { return scene::text::quoted(s); }  // TOML basic string
/// The shortest text that reads back to `v` exactly (a time of a [[timeline]] entry must).
std::string number(double v) { return scene::text::toml_number(v); }

scene::Document validated(const std::string& text, const std::string& path) {
  return scene::validate(scene::schema_for_text(text), text, path);
}

/// "part[2].generator" -> ("part", 2, "generator"); nullopt outside arrays of tables.
struct ElementKey {
  std::string array;
  std::size_t index = 0;
  std::string leaf;  ///< the key inside the element
};
std::optional<ElementKey> element_key(const std::string& key) {
  const auto lb = key.find('[');
  const auto rb = key.find("].");
  if (lb == std::string::npos || rb == std::string::npos || rb < lb) return std::nullopt;
  ElementKey e;
  e.array = key.substr(0, lb);
  e.index = std::stoul(key.substr(lb + 1, rb - lb - 1));
  e.leaf = key.substr(rb + 2);
  return e;
}

std::string element_name(const std::string& array, std::size_t index) {
  return array + "[" + std::to_string(index) + "]";
}

/// A name no entry of [[array]] has yet: base, base2, base3, ...
std::string unique_name(const scene::Document& d, const std::string& array, const std::string& base) {
  std::set<std::string> taken;
  const std::string key = array + ".name";
  for (std::size_t i = 0; i < d.count(array); ++i) taken.insert(d.string(key, i));
  if (!taken.count(base)) return base;
  for (int k = 2;; ++k)
    if (!taken.count(base + std::to_string(k))) return base + std::to_string(k);
}

/// Where a new part goes: to the right of everything the parts' origins and lengths reach.
double free_x(const scene::Document& d) {
  double x = 0.0;
  for (std::size_t i = 0; i < d.count("part"); ++i) {
    const std::vector<double> o = d.numbers("part.origin", i);
    x = std::max(x, o[0] + d.number("part.length", i));
  }
  return x;
}

Fields template_for(const scene::Document& d, const std::string& table) {
  const bool dynamic = d.string("scene.analysis") == "dynamic";
  if (table == "part") {
    const double x = d.count("part") ? free_x(d) + 0.5 : 0.0;
    return {{"name", quoted(unique_name(d, "part", "plate"))},
            {"generator", quoted("rectangular_plate")},
            {"origin", "[" + number(x) + ", 0.0, 0.0]"},
            {"length", "1.0"},
            {"width", "1.0"},
            {"n1", "8"},
            {"n2", "8"}};
  }
  if (table == "material")
    return {{"name", quoted(unique_name(d, "material", "steel"))},
            {"youngs_modulus", "2.1e11"},
            {"poisson_ratio", "0.3"},
            {"thickness", "0.01"},
            {"density", "7850.0"}};
  if (table == "bc")  // the edge x = 0 of the new problem's plate
    return {{"type", quoted("clamped")}, {"select", quoted("plane")}, {"point", "[0.0, 0.0, 0.0]"},
            {"normal", "[1.0, 0.0, 0.0]"}};
  if (table == "load")  // a force at the far corner, along z
    return {{"type", quoted("force")}, {"select", quoted("nearest")}, {"point", "[1.0, 1.0, 0.0]"},
            {"total", "[0.0, 0.0, 1.0]"}};
  if (table == "joint")
    return {{"type", quoted("spherical")}, {"select", quoted("nearest")}, {"point", "[0.0, 0.0, 0.0]"}};
  if (table == "probe")
    return {{"name", quoted(unique_name(d, "probe", "w"))},
            {"label", quoted("deflection along z")},
            {"select", quoted("nearest")},
            {"point", "[1.0, 1.0, 0.0]"},
            {"direction", "[0.0, 0.0, 1.0]"}};
  if (table == "metric") {
    if (d.count("probe") == 0)
      throw std::invalid_argument("a metric reads a probe: add a [[probe]] first");
    const std::string probe = d.string("probe.name", d.count("probe") - 1);
    return {{"name", quoted(unique_name(d, "metric", probe + (dynamic ? "_max" : "_final")))},
            {"kind", quoted(dynamic ? "max_abs" : "final")},
            {"probe", quoted(probe)}};
  }
  throw std::invalid_argument("the window has no template for [[" + table + "]] (it adds: part, material, bc, load, "
                              "joint, probe, metric)");
}

/// Keys of element (array, index) that depend on the choice `leaf` and no longer apply to
/// `value`, as --set names them, when they are present.
std::vector<std::string> keys_that_stop_applying(const scene::Schema& schema, const scene::Document& d,
                                                 const ElementKey& e, const std::string& value) {
  std::vector<std::string> drop;
  const std::string condition = e.array + "." + e.leaf;
  for (const scene::Schema::KeySpec& k : schema.keys())
    if (k.condition_key == condition && !k.applies(value) && d.present(k.path, e.index))
      drop.push_back(element_name(e.array, e.index) + k.path.substr(e.array.size()));
  return drop;
}

std::string listed(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

}  // namespace

std::string new_scene_text(const std::string& analysis, const std::string& name) {
  if (analysis != "static" && analysis != "dynamic")
    throw std::invalid_argument("a new problem is static or dynamic, not '" + analysis + "'");
  const bool dynamic = analysis == "dynamic";
  std::string t;
  t += "# A problem set up in the flexframe window.\n";
  t += "[scene]\n";
  t += "name = " + quoted(name) + "\n";
  t += "description = \"set up in the flexframe window\"\n";
  t += "model = \"shell\"\n";
  t += "analysis = \"" + analysis + "\"\n";
  t += dynamic ? "effects = [\"elastic\", \"inertia\", \"gravity\", \"hr\", \"ans\"]\n"
               : "effects = [\"elastic\", \"hr\", \"ans\"]\n";
  t += "\n[[part]]\nname = \"plate\"\ngenerator = \"rectangular_plate\"\nlength = 1.0\nwidth = 1.0\nn1 = 8\nn2 = 8\n";
  t += "\n[[material]]\nname = \"steel\"\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\nthickness = 0.01\n";
  if (dynamic) t += "density = 7850.0\n";
  if (dynamic)
    t += "\n[solver]\ndt = 0.002\nend = 0.5\n";
  else
    t += "\n[solver]\nmethod = \"load_control\"\nend = 1.0\ninitial_step = 0.25\nmax_step = 0.25\n";
  // statics are built only with a load and draw a load path, so they start with a force and a
  // probe at the plate's far corner
  if (!dynamic)
    t += "\n[[load]]\ntype = \"force\"\nselect = \"nearest\"\npoint = [1.0, 1.0, 0.0]\ntotal = [0.0, 0.0, 1.0]\n"
         "\n[[probe]]\nname = \"w\"\nlabel = \"deflection along z\"\nselect = \"nearest\"\npoint = [1.0, 1.0, 0.0]\n"
         "direction = [0.0, 0.0, 1.0]\n";
  t += "\n[output]\nframe_every = 1\nview = \"iso\"\ncolor_field = \"displacement\"\n";
  return t;
}

std::string mesh_scene_text(const std::string& mesh_path, const std::string& name) {
  const std::string text = new_scene_text("static", name);
  const std::string path = "new problem";
  const std::string bare = scene::text_without_keys(text, path, {"part[0].length", "part[0].width", "part[0].n1", "part[0].n2"});
  return scene::edited_scene_text(bare, path, {"part[0].generator=\"file\"", "part[0].file=" + quoted(mesh_path)});
}

std::vector<std::string> addable_tables(const scene::Schema& schema) {
  std::vector<std::string> out;
  for (const char* t : {"part", "material", "bc", "load", "joint", "probe", "metric"})
    if (schema.find_array(t)) out.push_back(t);
  return out;
}

DraftEdit with_entry_added(const std::string& text, const std::string& path, const std::string& table,
                           const Fields& fields) {
  const scene::Document d = validated(text, path);
  Fields keys = template_for(d, table);
  for (const auto& [k, raw] : fields) {
    const std::string v = scene::toml_value_as_set_reads_it(raw);
    const auto it = std::find_if(keys.begin(), keys.end(), [&](const auto& kv) { return kv.first == k; });
    if (it != keys.end())
      it->second = v;
    else
      keys.emplace_back(k, v);
  }
  // template keys that do not serve the entry's final choices (a point once select = patch_edge)
  const scene::Schema& schema = scene::schema_for_text(text);
  const auto value_of = [&](const std::string& key) -> std::string {
    for (const auto& [k, v] : keys)
      if (table + "." + k == key) return v.size() >= 2 && v.front() == '"' ? v.substr(1, v.size() - 2) : v;
    const scene::Schema::KeySpec* spec = schema.find_key(key);
    return spec ? scene::text::toml_value(spec->default_value) : "";
  };
  keys.erase(std::remove_if(keys.begin(), keys.end(),
                            [&](const auto& kv) {
                              const scene::Schema::KeySpec* spec = schema.find_key(table + "." + kv.first);
                              return spec && !spec->condition_key.empty() && !spec->applies(value_of(spec->condition_key));
                            }),
             keys.end());
  DraftEdit e;
  e.text = scene::text_with_element(text, path, table, keys);
  // a second part or material has to be named where it is used: say so instead of failing later
  if (table == "material" && d.count("material") == 1 && d.string("material.name", 0).empty())
    e.note = "the first material has no name yet; with two, each part names its own (part.material)";
  return e;
}

DraftEdit with_entry_removed(const std::string& text, const std::string& path, const std::string& table,
                             std::size_t index) {
  const scene::Document d = validated(text, path);
  const scene::Schema& schema = scene::schema_for_text(text);
  if (!d.declares_array(table) || index >= d.count(table))
    throw std::invalid_argument("there is no " + element_name(table, index) + " to remove");
  const scene::Schema::TableSpec* spec = schema.find_array(table);
  if (spec && d.count(table) <= spec->min_count)
    throw std::invalid_argument(element_name(table, index) + " is the last [[" + table +
                                "]] and the scene needs at least " + std::to_string(spec->min_count) +
                                "; add another before removing this one");
  return {scene::text_without_element(text, path, table, index), ""};
}

DraftEdit with_key_set(const std::string& text, const std::string& path, const std::string& key,
                       const std::string& value) {
  const scene::Schema& schema = scene::schema_for_text(text);
  // the value as the scene reads it (a bare word is a string), validated with the rest
  const scene::Document after = scene::validate(schema, text, path, {key + "=" + value});
  const std::optional<ElementKey> e = element_key(key);
  if (!e) return {scene::edited_scene_text(text, path, {key + "=" + value}), ""};
  const scene::Schema::KeySpec* spec = schema.find_key(e->array + "." + e->leaf);
  if (!spec || spec->kind != scene::Kind::Choice) return {scene::edited_scene_text(text, path, {key + "=" + value}), ""};
  const std::string chosen = after.string(e->array + "." + e->leaf, e->index);

  std::vector<std::string> dropped = keys_that_stop_applying(schema, after, *e, chosen);
  std::string next = scene::text_without_keys(text, path, dropped);
  std::vector<std::string> overrides = {key + "=" + value};
  std::vector<std::string> added;
  if (e->array == "part" && e->leaf == "generator") {
    // the dimensions the new generator cannot do without, at the schema's defaults
    for (const std::string& k : scene::generator_required_keys(chosen)) {
      const std::string path_k = "part." + k;
      if (after.present(path_k, e->index)) continue;
      const std::string set = element_name("part", e->index) + "." + k;
      overrides.push_back(set + "=" + scene::text::toml_value(schema.find_key(path_k)->default_value));
      added.push_back(set + " = " + scene::text::toml_value(schema.find_key(path_k)->default_value));
    }
  }
  DraftEdit out;
  out.text = scene::edited_scene_text(next, path, overrides);
  if (!dropped.empty())
    out.note = "dropped " + listed(dropped) + ": " + (dropped.size() == 1 ? "it does" : "they do") +
               " not apply with " + e->leaf + " = " + chosen;
  if (!added.empty())
    out.note += (out.note.empty() ? "" : "; ") + std::string("added ") + listed(added) + " (" + e->leaf + " = " +
                chosen + " needs " + (added.size() == 1 ? "it" : "them") + ")";
  return out;
}

const std::vector<MaterialPreset>& material_presets() {
  static const std::vector<MaterialPreset> presets = {
      {"steel", "structural steel: E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3",
       {{"youngs_modulus", "2.1e11"}, {"poisson_ratio", "0.3"}, {"density", "7850.0"}}},
      {"aluminium", "aluminium alloy: E = 70 GPa, nu = 0.33, rho = 2700 kg/m^3",
       {{"youngs_modulus", "7.0e10"}, {"poisson_ratio", "0.33"}, {"density", "2700.0"}}},
      {"CFRP ply (T300/5208)",
       "unidirectional carbon/epoxy ply, Tsai & Hahn, Introduction to Composite Materials (1980), Table 1.1: "
       "E1 = 181 GPa, E2 = 10.3 GPa, G12 = 7.17 GPa, nu12 = 0.28, rho = 1600 kg/m^3; G13 = G12, G23 = 3.5 GPa "
       "(transverse isotropy estimate E2 / (2 (1 + nu23)), nu23 = 0.47); strengths Xt = 1500, Xc = 1500, "
       "Yt = 40, Yc = 246, S = 68 MPa",
       {{"e1", "1.81e11"},
        {"e2", "1.03e10"},
        {"g12", "7.17e9"},
        {"g13", "7.17e9"},
        {"g23", "3.5e9"},
        {"nu12", "0.28"},
        {"density", "1600.0"},
        {"strength_xt", "1.5e9"},
        {"strength_xc", "1.5e9"},
        {"strength_yt", "4.0e7"},
        {"strength_yc", "2.46e8"},
        {"strength_s12", "6.8e7"}}},
  };
  return presets;
}

DraftEdit with_material_preset(const std::string& text, const std::string& path, std::size_t index,
                               const std::string& preset) {
  const auto p = std::find_if(material_presets().begin(), material_presets().end(),
                              [&](const MaterialPreset& m) { return m.name == preset; });
  if (p == material_presets().end()) {
    std::string names;
    for (const MaterialPreset& m : material_presets()) names += (names.empty() ? "" : ", ") + m.name;
    throw std::invalid_argument("no material preset '" + preset + "' (presets: " + names + ")");
  }
  const scene::Document d = validated(text, path);
  if (index >= d.count("material")) throw std::invalid_argument("there is no " + element_name("material", index));
  // every elastic and strength key of the entry goes; the preset brings its own
  static const std::vector<std::string> kElastic = {"youngs_modulus", "poisson_ratio", "density",     "e1",
                                                    "e2",             "g12",           "g13",         "g23",
                                                    "nu12",           "strength_xt",   "strength_xc", "strength_yt",
                                                    "strength_yc",    "strength_s12"};
  std::vector<std::string> drop;
  for (const std::string& k : kElastic)
    if (d.present("material." + k, index)) drop.push_back(element_name("material", index) + "." + k);
  const std::string bare = scene::text_without_keys(text, path, drop);
  std::vector<std::string> overrides;
  for (const auto& [k, v] : p->keys) overrides.push_back(element_name("material", index) + "." + k + "=" + v);
  // the entry takes the preset's name unless a part names it (renaming would cut that link)
  const std::string old_name = d.string("material.name", index);
  bool named_by_a_part = false;
  for (std::size_t i = 0; i < d.count("part"); ++i) named_by_a_part = named_by_a_part || d.string("part.material", i) == old_name;
  const std::string short_name = p->name.substr(0, p->name.find(' '));
  if (!named_by_a_part && old_name != short_name && (!old_name.empty() || d.count("material") > 1))
    overrides.push_back(element_name("material", index) + ".name=" + quoted(unique_name(d, "material", short_name)));
  std::string note = element_name("material", index) + " is " + p->about;
  // orthotropic plies have no default fibre direction (part.fibre_reference): every generated part
  // the material makes, alone or as a ply of a layup, gets "u" written into the scene, and the note
  // says which direction that is
  const bool orthotropic = std::any_of(p->keys.begin(), p->keys.end(), [](const auto& k) { return k.first == "e1"; });
  auto made_of_it = [&](std::size_t i) {
    const std::string& material = d.string("part.material", i);
    const std::string& layup = d.string("part.layup", i);
    if (!layup.empty()) {
      for (std::size_t l = 0; l < d.count("layup"); ++l)
        if (d.string("layup.name", l) == layup) {
          const std::vector<std::string> plies = d.strings("layup.plies", l);
          return std::find(plies.begin(), plies.end(), old_name) != plies.end();
        }
      return false;
    }
    return material == old_name || (material.empty() && d.count("material") == 1);
  };
  if (orthotropic)
    for (std::size_t i = 0; i < d.count("part"); ++i) {
      const std::string generator = d.string("part.generator", i);
      if (generator == "file" || d.present("part.fibre_reference", i) || !made_of_it(i)) continue;
      overrides.push_back(element_name("part", i) + ".fibre_reference=\"u\"");
      note += "; " + element_name("part", i) + ".fibre_reference = \"u\" written (0 degrees along u: " +
              scene::generator_grid_directions(generator) + "; set it to \"v\" or \"vector\" for another direction)";
    }
  return {scene::edited_scene_text(bare, path, overrides), note};
}

DraftEdit with_live_edit(const std::string& text, const std::string& path, const std::string& key,
                         const std::string& value, double at) {
  const scene::Document d = validated(text, path);
  const std::vector<std::pair<std::string, std::string>> change = scene::live_edit_as_timeline(d, key, value);
  const std::size_t n = d.count("timeline");
  // strictly ascending `at`: merge into an entry at the same time, else insert before the first later one
  for (std::size_t i = 0; i < n; ++i) {
    if (d.number("timeline.at", i) == at) {
      std::vector<std::string> overrides;
      for (const auto& [k, v] : change) overrides.push_back(element_name("timeline", i) + "." + k + "=" + v);
      return {scene::edited_scene_text(text, path, overrides), ""};
    }
  }
  std::size_t before = n;
  for (std::size_t i = 0; i < n; ++i)
    if (d.number("timeline.at", i) > at) {
      before = i;
      break;
    }
  Fields keys = {{"at", number(at)}};
  keys.insert(keys.end(), change.begin(), change.end());
  DraftEdit e;
  e.text = scene::text_with_element(text, path, "timeline", keys, before);
  e.note = "written as a [[timeline]] entry at " + number(at);
  return e;
}

std::string text_to_save(const std::string& text, const std::string& path, const std::string& save_path,
                         const std::string& opened_text, const std::string& opened_from) {
  const std::string stem = std::filesystem::path(save_path).stem().string();
  if (const std::string why = file_name_problem(stem); !why.empty())
    throw std::invalid_argument("the file name '" + stem + "' becomes scene.name, the output folder out/" + stem +
                                ", and " + why);
  std::string out = scene::edited_scene_text(text, path, {"scene.name=" + quoted(stem)});
  if (text != opened_text) {
    const std::string mark = "# Set up in the flexframe window";
    if (out.rfind(mark, 0) != 0)
      out = mark + (opened_from.empty() ? std::string(".\n")
                                        : " from " + opened_from +
                                              "; the comments below may describe that scene rather than this one.\n") +
            out;
  }
  return out;
}

}  // namespace ff::app::gui
