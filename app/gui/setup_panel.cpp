#include "app/gui/setup_panel.h"

#include <imgui.h>

#include <algorithm>

#include "app/gui/scene_draft.h"
#include "core/scene/scene.h"

namespace ff::app::gui {
namespace {

std::string entry_name(const std::string& table, std::size_t index) {
  return table + "[" + std::to_string(index) + "]";
}

/// The words that say what an entry is: its name, type or generator.
std::string describe(const scene::Document& d, const std::string& table, std::size_t i) {
  const std::vector<std::string> keys = d.element_key_paths(table);
  auto has = [&](const std::string& key) { return std::find(keys.begin(), keys.end(), table + "." + key) != keys.end(); };
  std::string s;
  if (has("name") && !d.string(table + ".name", i).empty()) s += d.string(table + ".name", i);
  if (has("type")) s += (s.empty() ? "" : " ") + d.string(table + ".type", i);
  if (has("generator")) s += (s.empty() ? "" : ", ") + d.string(table + ".generator", i);
  if (has("kind")) s += (s.empty() ? "" : ", ") + d.string(table + ".kind", i);
  if (has("select")) s += (s.empty() ? "" : ", ") + d.string(table + ".select", i);
  return s;
}

}  // namespace

SetupRequest add_entry(const std::string& table, std::vector<std::pair<std::string, std::string>> fields) {
  std::string what = "add " + table;
  for (const auto& [k, v] : fields) what += " " + k + "=" + v;
  return {what,
          [table, fields = std::move(fields)](const std::string& t, const std::string& p) {
            return with_entry_added(t, p, table, fields);
          },
          std::nullopt};
}

SetupRequest remove_entry(const std::string& table, std::size_t index) {
  return {"remove " + entry_name(table, index),
          [table, index](const std::string& t, const std::string& p) { return with_entry_removed(t, p, table, index); },
          std::nullopt};
}

SetupRequest material_preset(std::size_t index, const std::string& preset) {
  return {"preset " + entry_name("material", index) + " " + preset,
          [index, preset](const std::string& t, const std::string& p) { return with_material_preset(t, p, index, preset); },
          std::nullopt};
}

SetupRequest use_picked_nodes(const std::string& entry, const std::set<int>& nodes) {
  std::string list = "[";
  for (int n : nodes) list += (list.size() > 1 ? ", " : "") + std::to_string(n);
  list += "]";
  SetupRequest r;
  r.what = "use the " + std::to_string(nodes.size()) + " picked nodes for " + entry;
  r.op = [entry, list](const std::string& text, const std::string& path) {
    DraftEdit e = with_key_set(text, path, entry + ".select", "\"nodes\"");
    const DraftEdit n = with_key_set(e.text, path, entry + ".nodes", list);
    return DraftEdit{n.text, e.note};
  };
  return r;
}

SetupRequest use_patch_edge(const std::string& entry, const std::string& patch, const std::string& edge) {
  SetupRequest r;
  r.what = entry + " on the edge " + edge + " of " + patch;
  r.op = [entry, patch, edge](const std::string& text, const std::string& path) {
    DraftEdit e = with_key_set(text, path, entry + ".select", "\"patch_edge\"");
    e.text = with_key_set(e.text, path, entry + ".patch", "\"" + patch + "\"").text;
    e.text = with_key_set(e.text, path, entry + ".edge", "\"" + edge + "\"").text;
    return e;
  };
  return r;
}

std::vector<int> shown_nodes(const WorkerStatus& status, const std::string& shown) {
  std::vector<int> nodes;
  if (!status.selections || shown == "none") return nodes;
  // "all" leaves out entries that act on every node (a pressure on the whole body): marking
  // every node would hide what the others select; shown alone, such an entry marks them all
  const std::size_t every = status.info ? status.info->mesh.point_count() : 0;
  for (const scene::EntrySelection& e : *status.selections) {
    const bool whole = every > 0 && e.nodes.size() >= every;
    if ((shown == "all" && !whole) || shown == entry_name(e.table, e.index))
      nodes.insert(nodes.end(), e.nodes.begin(), e.nodes.end());
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

void SetupPanel::load(const WorkerStatus& status) {
  entries_.clear();
  addable_.clear();
  error_.clear();
  try {
    const scene::Schema& schema = scene::schema_for_text(status.scene_text);
    const scene::Document d = scene::validate(schema, status.scene_text, status.scene_path);
    addable_ = addable_tables(schema);
    for (const std::string& table : addable_) {
      for (std::size_t i = 0; i < d.count(table); ++i) {
        Entry e;
        e.table = table;
        e.index = i;
        e.label = entry_name(table, i) + " " + describe(d, table, i);
        e.selects = table == "bc" || table == "load" || table == "probe" || table == "joint";
        if (status.selections)
          for (const scene::EntrySelection& s : *status.selections)
            if (s.table == table && s.index == i) e.label += ": " + s.extent;
        entries_.push_back(std::move(e));
      }
    }
  } catch (const std::exception& ex) {
    error_ = ex.what();
  }
  add_choice_ = std::clamp(add_choice_, 0, std::max(0, static_cast<int>(addable_.size()) - 1));
}

std::vector<SetupRequest> SetupPanel::draw(const WorkerStatus& status, PickState& pick) {
  std::vector<SetupRequest> out;
  ImGui::TextUnformatted("new problem:");
  ImGui::SameLine();
  if (ImGui::SmallButton("static")) out.push_back({"new static problem", {}, std::string("static")});
  ImGui::SameLine();
  if (ImGui::SmallButton("dynamic")) out.push_back({"new dynamic problem", {}, std::string("dynamic")});
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("a 1 m x 1 m steel plate to start from: add supports, loads and probes, change its generator");
  if (!error_.empty()) {
    ImGui::TextWrapped("%s", error_.c_str());
    return out;
  }
  if (addable_.empty()) {
    ImGui::TextDisabled("this model has no entries to add (its keys are under Parameters)");
    return out;
  }
  ImGui::SetNextItemWidth(120);
  if (ImGui::BeginCombo("##add", addable_[static_cast<std::size_t>(add_choice_)].c_str())) {
    for (std::size_t i = 0; i < addable_.size(); ++i)
      if (ImGui::Selectable(addable_[i].c_str(), static_cast<int>(i) == add_choice_)) add_choice_ = static_cast<int>(i);
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (ImGui::Button("Add")) out.push_back(add_entry(addable_[static_cast<std::size_t>(add_choice_)]));
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("add an entry from a template; edit its keys under Parameters");

  // picking
  ImGui::Checkbox("pick nodes", &pick.picking);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("click the body to add or remove the nearest node, shift-drag a box to add every node in it; "
                      "then 'use picked' on a support, load, probe or joint");
  ImGui::SameLine();
  ImGui::Text("%zu picked", pick.nodes.size());
  if (!pick.nodes.empty()) {
    ImGui::SameLine();
    if (ImGui::SmallButton("clear")) pick.nodes.clear();
  }
  ImGui::TextUnformatted("show:");
  ImGui::SameLine();
  if (ImGui::RadioButton("all", pick.shown == "all")) pick.shown = "all";
  ImGui::SameLine();
  if (ImGui::RadioButton("none", pick.shown == "none")) pick.shown = "none";

  // one line per entry: remove, what it is and what it selects; below it, indented, its controls
  for (const Entry& e : entries_) {
    const std::string name = entry_name(e.table, e.index);
    ImGui::PushID(name.c_str());
    if (ImGui::SmallButton("x")) out.push_back(remove_entry(e.table, e.index));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("remove %s", name.c_str());
    ImGui::SameLine();
    ImGui::TextUnformatted(e.label.c_str());
    if (e.selects || e.table == "material") ImGui::Indent(22.0f);
    if (e.selects) {
      if (ImGui::RadioButton("show", pick.shown == name)) pick.shown = pick.shown == name ? "all" : name;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("show only the nodes %s acts on", name.c_str());
      if (status.patch_edges && !status.patch_edges->empty()) {
        // an edge of a generated part, from the list of the generators' edge names
        ImGui::SameLine();
        ImGui::SetNextItemWidth(110);
        if (ImGui::BeginCombo("##edge", "edge...")) {
          for (const auto& [patch, edge] : *status.patch_edges)
            if (ImGui::Selectable((patch + ": " + edge).c_str())) out.push_back(use_patch_edge(name, patch, edge));
          ImGui::EndCombo();
        }
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("select an edge of a part by its name (select = \"patch_edge\")");
      }
      if (!pick.nodes.empty()) {
        ImGui::SameLine();
        if (ImGui::SmallButton("use picked")) out.push_back(use_picked_nodes(name, pick.nodes));
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("select = \"nodes\" with the %zu picked nodes", pick.nodes.size());
      }
    }
    if (e.table == "material") {
      ImGui::SetNextItemWidth(200);
      if (ImGui::BeginCombo("##preset", "preset...")) {
        for (const MaterialPreset& m : material_presets()) {
          if (ImGui::Selectable(m.name.c_str())) out.push_back(material_preset(e.index, m.name));
          if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", m.about.c_str());
        }
        ImGui::EndCombo();
      }
    }
    if (e.selects || e.table == "material") ImGui::Unindent(22.0f);
    ImGui::PopID();
  }
  return out;
}

}  // namespace ff::app::gui
