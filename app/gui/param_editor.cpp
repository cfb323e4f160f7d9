#include "app/gui/param_editor.h"

#include <sstream>

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cctype>

#include "core/scene/scene.h"
#include "core/scene/schema_text.h"

namespace ff::app::gui {
namespace {

using scene::Kind;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string quoted(const std::string& s) { return scene::text::quoted(s); }  // TOML basic string

/// "\"efg\"" -> "efg" (strings and choices are edited without their quotes).
std::string unquoted(const std::string& toml) {
  if (toml.size() >= 2 && toml.front() == '"' && toml.back() == '"') {
    std::string out;
    for (std::size_t i = 1; i + 1 < toml.size(); ++i) {
      if (toml[i] == '\\' && i + 2 < toml.size()) ++i;
      out += toml[i];
    }
    return out;
  }
  return toml;
}

std::string list_text(const std::vector<std::string>& items) {
  std::string s = "[";
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + quoted(items[i]);
  return s + "]";
}

std::string allowed_text(const scene::Schema::KeySpec& k) {
  switch (k.kind) {
    case Kind::Number:
    case Kind::NumberList: return k.range.text();
    case Kind::Integer: return k.int_range.text();
    case Kind::Boolean: return "true, false";
    case Kind::Choice:
    case Kind::StringList: {
      std::string s;
      for (const auto& c : k.choices) s += (s.empty() ? "" : ", ") + c;
      return s.empty() ? "any" : s;
    }
    case Kind::String: return "any";
  }
  return "";
}

/// The unit shown beside a value: the schema's, else one the key's description ends with
/// ("time step [s]"), else none (a dimensionless key, or one in the scene's own consistent units).
std::string unit_of(const scene::Schema::KeySpec& k) {
  if (!k.unit.empty()) return k.unit;
  const std::size_t open = k.doc.rfind('[');
  if (open == std::string::npos || k.doc.empty() || k.doc.back() != ']') return "";
  const std::string inner = k.doc.substr(open + 1, k.doc.size() - open - 2);
  const bool plain = !inner.empty() && inner.size() <= 12 && inner.find(' ') == std::string::npos;
  return plain ? inner : "";
}

}  // namespace

std::vector<ParamItem> scene_params(const std::string& text, const std::string& path, const std::string& opened_text) {
  const scene::Schema& schema = scene::schema_for_text(text);
  const scene::Document doc = scene::validate(schema, text, path);
  // what the scene was when opened; an opened text that no longer validates marks nothing
  std::optional<scene::Document> opened;
  try {
    if (&scene::schema_for_text(opened_text) == &schema) opened = scene::validate(schema, opened_text, path);
  } catch (const scene::SceneError&) {
  }
  auto differs = [&](const std::string& key, const std::string& value, std::optional<std::size_t> index) {
    if (!opened) return false;
    if (!index) return opened->value_text(key) != value;
    const std::string array = schema.array_of(key);
    return *index >= opened->count(array) || opened->value_text(key, *index) != value;
  };
  std::vector<ParamItem> items;
  for (const std::string& k : doc.key_paths()) {
    if (k == "scene.model") continue;
    ParamItem it;
    it.key = k;
    const auto dot = k.rfind('.');
    it.group = dot == std::string::npos ? "" : k.substr(0, dot);
    it.name = dot == std::string::npos ? k : k.substr(dot + 1);
    it.spec = schema.find_key(k);
    it.value = doc.value_text(k);
    it.where = doc.where(k);
    it.edited = differs(k, it.value, std::nullopt);
    if (it.spec) items.push_back(it);
  }
  for (const std::string& a : doc.array_paths()) {
    for (std::size_t i = 0; i < doc.count(a); ++i) {
      for (const std::string& k : doc.element_key_paths(a)) {
        const scene::Schema::KeySpec* spec = schema.find_key(k);
        if (!spec) continue;
        // a key of another generator or selection is not listed (switching drops it)
        if (!spec->condition_key.empty() && !spec->applies(doc.string(spec->condition_key, i)) && !doc.present(k, i))
          continue;
        ParamItem it;
        it.group = a + "[" + std::to_string(i) + "]";
        it.name = k.substr(a.size() + 1);
        it.key = it.group + "." + it.name;
        it.spec = spec;
        it.value = doc.value_text(k, i);
        it.where = doc.where(k, i);
        it.edited = differs(k, it.value, i);
        items.push_back(it);
      }
    }
  }
  // rows of one table together, tables in order of first appearance
  std::vector<std::string> order;
  for (const ParamItem& it : items)
    if (std::find(order.begin(), order.end(), it.group) == order.end()) order.push_back(it.group);
  std::stable_sort(items.begin(), items.end(), [&](const ParamItem& a, const ParamItem& b) {
    return std::find(order.begin(), order.end(), a.group) < std::find(order.begin(), order.end(), b.group);
  });
  return items;
}

void draw_live_tag() {
  // a small filled badge, the same in the list and in its header
  const ImVec2 size = ImGui::CalcTextSize("live");
  const ImVec2 pad(3.0f, 0.0f);
  const ImVec2 at = ImGui::GetCursorScreenPos();
  ImGui::GetWindowDrawList()->AddRectFilled(at, ImVec2(at.x + size.x + 2 * pad.x, at.y + size.y),
                                            ImGui::GetColorU32(ImVec4(0.18f, 0.55f, 0.25f, 1.0f)), 3.0f);
  ImGui::GetWindowDrawList()->AddText(ImVec2(at.x + pad.x, at.y), IM_COL32(255, 255, 255, 255), "live");
  ImGui::Dummy(ImVec2(size.x + 2 * pad.x, size.y));
}

std::vector<std::string> ParamEditor::live_keys() const {
  std::vector<std::string> keys;
  for (const Row& r : rows_)
    if (r.item.spec->live) keys.push_back(r.item.key);
  return keys;
}

void ParamEditor::load(const std::string& text, const std::string& path, const std::string& opened_text) {
  rows_.clear();
  error_.clear();
  try {
    for (ParamItem& it : scene_params(text, path, opened_text)) {
      Row r;
      r.item = std::move(it);
      const Kind kind = r.item.spec->kind;
      r.buffer = (kind == Kind::String || kind == Kind::Choice) ? unquoted(r.item.value) : r.item.value;
      r.flag = r.item.value == "true";
      if (kind == Kind::StringList && !r.item.spec->choices.empty()) {
        for (const std::string& c : r.item.spec->choices)
          if (r.item.value.find(quoted(c)) != std::string::npos) r.selected.push_back(c);
      }
      rows_.push_back(std::move(r));
    }
  } catch (const std::exception& e) {
    error_ = e.what();
  }
}

std::vector<std::pair<std::string, std::string>> ParamEditor::draw() {
  std::vector<std::pair<std::string, std::string>> edits;
  if (!error_.empty()) {
    ImGui::TextWrapped("%s", error_.c_str());
    return edits;
  }
  ImGui::SetNextItemWidth(-1);
  ImGui::InputTextWithHint("##filter", "filter keys (e.g. dt, thickness, effects)", &filter_);
  const std::string f = lower(filter_);
  const ImVec4 edited_color(0.80f, 0.35f, 0.05f, 1.0f);

  std::size_t i = 0;
  while (i < rows_.size()) {
    // one tree node per table; rows of a table are consecutive
    const std::string group = rows_[i].item.group;
    std::size_t end = i;
    bool any_match = false;
    while (end < rows_.size() && rows_[end].item.group == group) {
      any_match = any_match || f.empty() || lower(rows_[end].item.key).find(f) != std::string::npos;
      ++end;
    }
    if (!any_match) {
      i = end;
      continue;
    }
    const std::string title = group.empty() ? "(top level)" : group;
    // the time-stepping tables start open: the keys people try first
    const bool stepping = group == "solver" || group == "time" || group == "integrator";
    ImGui::PushID(title.c_str());
    if (!f.empty()) ImGui::SetNextItemOpen(true);  // a filter shows every match
    const bool open = ImGui::TreeNodeEx(title.c_str(), stepping ? ImGuiTreeNodeFlags_DefaultOpen : 0);
    if (open) {
      // units sit in a column of their own width at the right of the values, so the fields of a
      // table line up
      float unit_room = 0.0f;
      for (std::size_t r = i; r < end; ++r) {
        const std::string unit = unit_of(*rows_[r].item.spec);
        if (!unit.empty())
          unit_room = std::max(unit_room, ImGui::CalcTextSize(unit.c_str()).x + ImGui::GetStyle().ItemInnerSpacing.x);
      }
      if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_SizingStretchProp)) {
        ImGui::TableSetupColumn("key", ImGuiTableColumnFlags_WidthStretch, 0.42f);
        ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch, 0.58f);
        for (std::size_t r = i; r < end; ++r) {
          Row& row = rows_[r];
          const ParamItem& it = row.item;
          if (!f.empty() && lower(it.key).find(f) == std::string::npos) continue;
          const auto& spec = *it.spec;
          ImGui::PushID(it.key.c_str());
          ImGui::TableNextRow();
          ImGui::TableSetColumnIndex(0);
          if (it.edited)
            ImGui::TextColored(edited_color, "%s", it.name.c_str());
          else
            ImGui::TextUnformatted(it.name.c_str());
          bool key_hovered = ImGui::IsItemHovered();
          if (spec.live) {
            ImGui::SameLine();
            draw_live_tag();
            key_hovered = key_hovered || ImGui::IsItemHovered();
          }
          if (key_hovered) {
            ImGui::BeginTooltip();
            ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
            ImGui::Text("%s", it.key.c_str());
            ImGui::TextWrapped("%s", spec.doc.c_str());
            if (!unit_of(spec).empty()) ImGui::Text("unit: %s", unit_of(spec).c_str());
            ImGui::Text("allowed: %s", allowed_text(spec).c_str());
            if (spec.live) ImGui::Text("live: an edit changes the running model from its next step");
            ImGui::Text("from: %s", it.where.c_str());
            ImGui::PopTextWrapPos();
            ImGui::EndTooltip();
          }
          ImGui::TableSetColumnIndex(1);
          // the unit beside the value
          const std::string unit = unit_of(spec);
          const bool show_unit = !unit.empty() && !(spec.kind == Kind::StringList && !spec.choices.empty());
          ImGui::SetNextItemWidth(unit_room > 0.0f ? -unit_room : -1.0f);
          switch (spec.kind) {
            case Kind::Boolean:
              if (ImGui::Checkbox("##v", &row.flag)) edits.emplace_back(it.key, row.flag ? "true" : "false");
              break;
            case Kind::Choice:
              if (ImGui::BeginCombo("##v", row.buffer.c_str())) {
                for (const std::string& c : spec.choices) {
                  if (ImGui::Selectable(c.c_str(), c == row.buffer) && c != row.buffer) {
                    row.buffer = c;
                    edits.emplace_back(it.key, quoted(c));
                  }
                }
                ImGui::EndCombo();
              }
              break;
            case Kind::StringList:
              if (!spec.choices.empty()) {
                // effects and other sets of names: one checkbox each
                bool changed = false;
                for (const std::string& c : spec.choices) {
                  bool on = std::find(row.selected.begin(), row.selected.end(), c) != row.selected.end();
                  if (ImGui::Checkbox(c.c_str(), &on)) {
                    changed = true;
                    if (on)
                      row.selected.push_back(c);
                    else
                      row.selected.erase(std::find(row.selected.begin(), row.selected.end(), c));
                  }
                }
                if (changed) edits.emplace_back(it.key, list_text(row.selected));
                break;
              }
              [[fallthrough]];
            default: {
              const ImGuiInputTextFlags tf =
                  spec.kind == Kind::Number || spec.kind == Kind::Integer ? ImGuiInputTextFlags_CharsScientific : 0;
              ImGui::InputText("##v", &row.buffer, tf);
              if (ImGui::IsItemDeactivatedAfterEdit()) {
                const std::string v = spec.kind == Kind::String ? quoted(row.buffer) : row.buffer;
                if (v != it.value) edits.emplace_back(it.key, v);
              }
            }
          }
          if (show_unit) {
            ImGui::SameLine(0.0f, ImGui::GetStyle().ItemInnerSpacing.x);
            ImGui::TextDisabled("%s", unit.c_str());
          }
          if (refusal_ && refusal_->key == it.key) {
            // the reason under the key it refused, in the panel, not only in a tooltip
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(1);
            ImGui::PushTextWrapPos(0.0f);
            ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1.0f), "%s", refusal_->text.c_str());
            ImGui::PopTextWrapPos();
          }
          ImGui::PopID();
        }
        ImGui::EndTable();
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
    i = end;
  }
  for (const auto& e : edits)
    if (refusal_ && refusal_->key == e.first) refusal_.reset();
  return edits;
}

std::optional<Refusal> readable_refusal(const std::string& message) {
  const std::string suffix = " refused:";
  const std::size_t eol = message.find('\n');
  const std::string head = message.substr(0, eol);
  if (head.size() <= suffix.size() || head.compare(head.size() - suffix.size(), suffix.size(), suffix) != 0)
    return std::nullopt;
  const std::string what = head.substr(0, head.size() - suffix.size());
  Refusal r;
  std::string value;
  if (what.rfind("set ", 0) == 0 && what.find(" = ") != std::string::npos) {
    r.key = what.substr(4, what.find(" = ") - 4);
    value = what.substr(what.find(" = ") + 3);
  }
  // the reasons, without the CLI's "--set KEY=VALUE: " and "key 'KEY': " prefixes
  std::string reasons;
  std::istringstream lines(eol == std::string::npos ? "" : message.substr(eol + 1));
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("--set ", 0) == 0 && line.find(": ") != std::string::npos) line = line.substr(line.find(": ") + 2);
    const std::string key_prefix = "key '" + r.key + "': ";
    if (!r.key.empty() && line.rfind(key_prefix, 0) == 0) line = line.substr(key_prefix.size());
    if (line.empty()) continue;
    reasons += (reasons.empty() ? "" : "; ") + line;
  }
  if (reasons.empty()) reasons = "no reason given";
  if (!r.key.empty())
    r.text = r.key + " = " + value + " was not applied: " + reasons + ". Nothing changed; the run goes on as it was.";
  else
    r.text = "Could not " + what + ": " + reasons + ". Nothing changed.";
  return r;
}

}  // namespace ff::app::gui
