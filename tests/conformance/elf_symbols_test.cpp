#include "elf_symbols.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

using clothlab::conformance::exported_symbols;

TEST(ExportedSymbols, APluginBuiltWithTheHelperExportsOnlyItsEntry) {
  const std::vector<std::string> names =
      exported_symbols(std::string(CONFORMANCE_PLUGIN_DIR) + "/c_euler.so");
  EXPECT_EQ(names, std::vector<std::string>{"clothlab_plugin_entry"});
}

TEST(ExportedSymbols, AnOrdinaryLibraryExportsMany) {
  // An ordinary shared library: its dynamic symbol table lists hundreds of functions.
  const std::vector<std::string> names = exported_symbols("/lib/x86_64-linux-gnu/libm.so.6");
  EXPECT_GT(names.size(), 100u);
}

TEST(ExportedSymbols, RejectsAFileThatIsNotElf) {
  EXPECT_THROW(exported_symbols(NOT_A_PLUGIN), std::runtime_error);
  EXPECT_THROW(exported_symbols("/nonexistent/plugin.so"), std::runtime_error);
}
