#pragma once
// A command line option whose value is a core enum: accepted values, the choices in --help and the parse all come
// from the enum's one name table (core/common/enum_names.hpp), so a name added to the table is an accepted value
// of every flag that takes the enum, with no list here to update.
//
//   add_enum_option(sub, "--method", options->method, kMapMethodNames, "Spherical map method");
//
// The target is an E (its current value is the default shown) or a std::optional<E> (absent: the caller's default,
// given as `shown_default` for --help).

#include <cstddef>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/common/enum_names.hpp"

namespace wish::cli {

template <class E, std::size_t N>
CLI::Option* add_enum_option(CLI::App& app, const std::string& flag, E& target, const EnumNames<E, N>& names,
                             const std::string& help) {
  CLI::Option* option = app.add_option_function<std::string>(
      flag, [&target, &names](const std::string& value) { target = names.parse(value, "value", "value"); }, help);
  option->check(CLI::IsMember(names.names()));  // CLI11's own error names the flag and the choices
  option->default_str(names.name(target));
  return option;
}

template <class E, std::size_t N>
CLI::Option* add_enum_option(CLI::App& app, const std::string& flag, std::optional<E>& target,
                             const EnumNames<E, N>& names, E shown_default, const std::string& help) {
  CLI::Option* option = app.add_option_function<std::string>(
      flag, [&target, &names](const std::string& value) { target = names.parse(value, "value", "value"); }, help);
  option->check(CLI::IsMember(names.names()));
  option->default_str(names.name(shown_default));
  return option;
}

}  // namespace wish::cli
