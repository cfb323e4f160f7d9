#pragma once
/// \file schema_value.h
/// The kinds and values of scene keys (schema.h declares and validates them; schema_text.h
/// writes them as text): apart so that the text helpers need no Schema.

#include <string>
#include <variant>
#include <vector>

namespace ff::scene {

/// Kinds of declared keys.
enum class Kind { Number, Integer, Boolean, String, Choice, NumberList, StringList };

/// A validated (or default) value. monostate = no value (absent key of an absent table).
using Value = std::variant<std::monostate, double, long long, bool, std::string,
                           std::vector<double>, std::vector<std::string>>;

}  // namespace ff::scene
