// Lab harness, not built by CMake: xpbd's row kernels (plugins/integrators/xpbd_row_kernel.hpp)
// on a 16-row grid whose data stays in L1, timed per 8 columns of a row, for row lengths
// (`cols`) whose rows start on or off a 32-byte boundary and for the stencils' partner offsets.
// It shows what the rows' alignment costs the kernels, apart from the rest of a substep.
//
//   g++ -O3 -fopenmp -fno-math-errno -fno-trapping-math -fno-tree-slp-vectorize -std=c++20
//     -mavx2 -mfma -DNDEBUG -Icore/src -Iplugins/integrators -Icore/include
//     lab/bench/xpbd_row_alignment.cpp -o /tmp/xpbd_row_alignment
//   /tmp/xpbd_row_alignment COLS KIND DELTA
//
// KIND 0: springs to the next rows (partner offset cols + DELTA: 0 (1,0), 1 (1,1), -1 (1,-1),
// cols (2,0)); KIND 1 or 2: in-row springs of step KIND, parity DELTA. Prints the fastest of seven
// trials in nanoseconds per 8 columns of a row (the rows kernel: a block of eight springs).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "float_lanes.hpp"
#include "xpbd_color_row.hpp"
#include "xpbd_row_kernel.hpp"

int main(int argc, char** argv) {
  using clothlab::builtin::ColorRow;
  if (argc != 4) {
    std::fprintf(stderr, "usage: xpbd_row_alignment COLS KIND DELTA\n");
    return 1;
  }
  const std::size_t cols = std::strtoul(argv[1], nullptr, 10);
  const int kind = std::atoi(argv[2]), delta = std::atoi(argv[3]);
  constexpr std::size_t rows = 16, repetitions = 4000;
  const std::size_t n = rows * cols, stride = n + 64;
  // x and dx in one 64-byte aligned buffer; row r starts at element r cols of each component.
  std::vector<float> buffer(6 * stride + 16), inverse_mass(stride, 1.0f);
  float* const x = buffer.data() +
                   (16 - reinterpret_cast<std::uintptr_t>(buffer.data()) / sizeof(float) % 16) % 16;
  float* const dx = x + 3 * stride;
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = 0.01f * static_cast<float>(i % cols);
    x[i + stride] = -0.01f * static_cast<float>(i / cols);
    x[i + 2 * stride] = 1e-3f * static_cast<float>(i % 7);
    for (std::size_t k = 0; k < 3; ++k)
      dx[i + k * stride] = 1e-5f * static_cast<float>((i + k) % 13);
  }
  const bool in_row = kind != 0;
  const std::size_t offset =
      in_row ? static_cast<std::size_t>(kind) : static_cast<std::size_t>(int64_t(cols) + delta);
  const ColorRow<float> row{.x = x,
                            .displacement = dx,
                            .inverse_mass = inverse_mass.data(),
                            .lambda = nullptr,
                            .stride = stride,
                            .first = 0,
                            .count = in_row ? cols : cols - 2,
                            .offset = offset,
                            .alternates = in_row,
                            .alternation_shift = kind == 2 ? 1u : 0u,
                            .parity = static_cast<uint32_t>(delta & 1),
                            .rest = 0.01f,
                            .stiffness = 1e-3f,
                            .damping = 1e-4f,
                            .fresh = true,
                            .keep_lambda = false,
                            .uniform_weight = 1.0f,
                            .varied_begin = 0,
                            .varied_end = 0};
  const std::size_t last_row = in_row ? rows : rows - 2;  // a (2,0) partner two rows down
  double best = 1e30;
  for (int trial = 0; trial < 7; ++trial) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k < repetitions; ++k)
      for (std::size_t r = 0; r < last_row; ++r) {
        ColorRow<float> job = row;
        job.first = r * cols;
        clothlab::builtin::project_row(job);
      }
    best = std::min(
        best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  // Per 8 columns of a row: the same work at 300 and 304 columns, whatever the kernels' tails.
  const double eighths =
      static_cast<double>(repetitions * last_row) * static_cast<double>(cols) / 8;
  std::printf("cols %zu kind %d delta %d: %.2f ns per 8 columns of a row\n", cols, kind, delta,
              best * 1e9 / eighths);
  return 0;
}
