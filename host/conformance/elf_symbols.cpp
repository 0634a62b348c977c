#include "elf_symbols.hpp"

#include <elf.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace clothlab::conformance {
namespace {

std::vector<char> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Copies a T out of `bytes` at `offset`, checking bounds (the file may be malformed).
template <class T>
T read_at(const std::vector<char>& bytes, uint64_t offset, const std::string& path) {
  if (offset > bytes.size() || bytes.size() - offset < sizeof(T))
    throw std::runtime_error(path + ": truncated ELF file");
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

bool is_exported(const Elf64_Sym& symbol) {
  const unsigned binding = ELF64_ST_BIND(symbol.st_info);
  const unsigned type = ELF64_ST_TYPE(symbol.st_info);
  const unsigned visibility = ELF64_ST_VISIBILITY(symbol.st_other);
  const bool global = binding == STB_GLOBAL || binding == STB_WEAK || binding == STB_GNU_UNIQUE;
  const bool visible = visibility == STV_DEFAULT || visibility == STV_PROTECTED;
  const bool named_object = type != STT_SECTION && type != STT_FILE;
  return symbol.st_shndx != SHN_UNDEF && global && visible && named_object;
}

}  // namespace

std::vector<std::string> exported_symbols(const std::string& path) {
  const std::vector<char> bytes = read_file(path);
  const auto header = read_at<Elf64_Ehdr>(bytes, 0, path);
  if (std::memcmp(header.e_ident, ELFMAG, SELFMAG) != 0)
    throw std::runtime_error(path + ": not an ELF file");
  if (header.e_ident[EI_CLASS] != ELFCLASS64)
    throw std::runtime_error(path + ": not a 64-bit ELF file");

  std::vector<std::string> names;
  for (uint16_t i = 0; i < header.e_shnum; ++i) {
    const auto section =
        read_at<Elf64_Shdr>(bytes, header.e_shoff + uint64_t{i} * header.e_shentsize, path);
    if (section.sh_type != SHT_DYNSYM || section.sh_entsize == 0) continue;
    const auto strings = read_at<Elf64_Shdr>(
        bytes, header.e_shoff + uint64_t{section.sh_link} * header.e_shentsize, path);
    const uint64_t count = section.sh_size / section.sh_entsize;
    for (uint64_t k = 1; k < count; ++k) {  // entry 0 is the reserved null symbol
      const auto symbol =
          read_at<Elf64_Sym>(bytes, section.sh_offset + k * section.sh_entsize, path);
      if (!is_exported(symbol)) continue;
      const uint64_t name_offset = strings.sh_offset + symbol.st_name;
      if (name_offset >= bytes.size()) throw std::runtime_error(path + ": bad symbol name offset");
      const char* name = bytes.data() + name_offset;
      names.emplace_back(name, strnlen(name, bytes.size() - name_offset));
    }
  }
  return names;
}

}  // namespace clothlab::conformance
