// The shared assembly pieces (core/assembly): unknown numbering, block pattern and element
// scatter, checked against a plain dense assembly of the same element blocks.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/assembly/block_pattern.h"
#include "core/assembly/dof_map.h"
#include "core/assembly/element_thread_pool.h"
#include "core/assembly/element_threads.h"
#include "core/assembly/node_frames.h"

using namespace ff::assembly;

TEST(Assembly, UnknownsAreNumberedNodeByNodeSlotsAscending) {
  // node 1 has 5 DoFs, node 2 has its translations restrained
  const DofMap d(3, [](int node, int slot) { return !(node == 1 && slot == 5) && !(node == 2 && slot < 3); });
  EXPECT_EQ(d.size(), 6 + 5 + 3);
  EXPECT_EQ(d.equation(0, 0), 0);
  EXPECT_EQ(d.equation(1, 4), 10);
  EXPECT_EQ(d.equation(1, 5), -1);
  EXPECT_EQ(d.equation(2, 2), -1);
  EXPECT_EQ(d.equation(2, 3), 11);
  for (int k = 0; k < d.size(); ++k) { EXPECT_EQ(d.equation(d.unknown(k).node, d.unknown(k).slot), k); }
}

TEST(Assembly, ScatterAddEqualsDenseAssembly) {
  // two quads sharing an edge on 6 nodes, one slot absent here and there
  const std::array<int, 4> q0{0, 1, 4, 3}, q1{1, 2, 5, 4};
  const DofMap d(6, [](int node, int slot) { return (node + slot) % 5 != 4; });
  BlockPattern p;
  p.add_element(q0);
  p.add_element(q1);
  p.build(d);
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(d.size(), d.size());
  Eigen::SparseMatrix<double> K;
  p.zeroed(K);
  for (const auto& q : {q0, q1}) {
    Eigen::Matrix<double, 24, 24> Ke;
    for (int i = 0; i < 24; ++i)
      for (int j = 0; j < 24; ++j) Ke(i, j) = u(g);
    const std::array<int, 576> idx = p.element_scatter(d, q);
    for (int i = 0; i < 24; ++i)
      for (int j = 0; j < 24; ++j) {
        const int a = d.equation(q[i / 6], i % 6), b = d.equation(q[j / 6], j % 6);
        if (a >= 0 && b >= 0) dense(a, b) += Ke(i, j);
        if (idx[i * 24 + j] >= 0) K.valuePtr()[idx[i * 24 + j]] += Ke(i, j);
        EXPECT_EQ(idx[i * 24 + j] >= 0, a >= 0 && b >= 0);
      }
  }
  EXPECT_EQ((Eigen::MatrixXd(K) - dense).cwiseAbs().maxCoeff(), 0.0);
  // nodes 0 and 2 share no element: no entries between them
  EXPECT_EQ(p.value_index(d.equation(0, 0), d.equation(2, 0)), -1);
}

TEST(Assembly, NodeScatterAndZeroedReuseThePattern) {
  const std::array<int, 4> q0{0, 1, 3, 2};
  const DofMap d(4, [](int node, int slot) { return !(node == 2 && slot == 5) && !(node == 3 && slot < 3); });
  BlockPattern p;
  p.add_element(q0);
  p.build(d);
  for (int I = 0; I < 4; ++I) {
    const std::array<int, 36> idx = p.node_scatter(d, I);
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const int a = d.equation(I, i), b = d.equation(I, j);
        EXPECT_EQ(idx[6 * i + j], a >= 0 && b >= 0 ? p.value_index(a, b) : -1) << I << " " << i << " " << j;
      }
  }
  // a matrix with the pattern keeps its arrays and loses its values
  Eigen::SparseMatrix<double> K;
  p.zeroed(K);
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 7.0);
  const int* inner = K.innerIndexPtr();
  p.zeroed(K);
  EXPECT_EQ(K.innerIndexPtr(), inner);
  EXPECT_EQ(Eigen::MatrixXd(K).cwiseAbs().maxCoeff(), 0.0);
  // one with another pattern of the same size and count gets the pattern
  Eigen::SparseMatrix<double> other(d.size(), d.size());
  for (int k = 0; k < p.pattern().nonZeros(); ++k) other.insert(k % d.size(), (k / d.size()) % d.size()) = 1.0;
  other.makeCompressed();
  ASSERT_EQ(other.nonZeros(), p.pattern().nonZeros());
  p.zeroed(other);
  EXPECT_TRUE(std::equal(other.innerIndexPtr(), other.innerIndexPtr() + other.nonZeros(), p.pattern().innerIndexPtr()));
  EXPECT_TRUE(std::equal(other.outerIndexPtr(), other.outerIndexPtr() + d.size() + 1, p.pattern().outerIndexPtr()));
  EXPECT_EQ(Eigen::MatrixXd(other).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Assembly, CornerFrameTurnsTheNodeFrameOntoTheCornerDirector) {
  const Eigen::Matrix3d R0 = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  const CornerFrame c = corner_frame(R0, n);
  EXPECT_LT((c.frame.col(2) - n).norm(), 1e-14);
  EXPECT_LT((R0 * c.turn - c.frame).norm(), 1e-14);
  EXPECT_LT((c.turn.transpose() * c.turn - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  const CornerFrame plain = corner_frame(R0, R0.col(2));
  EXPECT_EQ((plain.frame - R0).norm(), 0.0);  // a plain corner keeps the node frame exactly
}

// The element loop (element_threads.h): every item once, in contiguous ranges that are the same
// on every call, for any thread count (more threads than items included); one thread fewer while
// the renderer is busy; an exception inside reaches the caller.
TEST(Assembly, ElementLoopCoversEveryItemOnceInFixedChunks) {
  for (int threads : {1, 2, 3, 7}) {
    const ElementThreads passed{threads, nullptr};
    EXPECT_EQ(passed.now(), threads);
    for (int count : {0, 1, 2, 5, 450, 1001}) {
      std::vector<std::atomic<int>> seen(count);
      std::vector<std::pair<int, int>> first, second;
      std::mutex m;
      for (auto* ranges : {&first, &second})
        for_each_chunk(passed, count, [&](int begin, int end) {
          ASSERT_LE(0, begin);
          ASSERT_LE(begin, end);
          ASSERT_LE(end, count);
          if (ranges == &first)
            for (int k = begin; k < end; ++k) ++seen[k];
          std::lock_guard<std::mutex> lock(m);
          ranges->emplace_back(begin, end);
        });
      for (int k = 0; k < count; ++k) { EXPECT_EQ(seen[k], 1) << "item " << k << ", " << threads << " threads"; }
      std::sort(first.begin(), first.end());
      std::sort(second.begin(), second.end());
      EXPECT_EQ(first, second);
      if (count > 0) {
        EXPECT_EQ(static_cast<int>(first.size()), std::min(threads, count));
      }
    }
  }
  std::atomic<bool> busy{true};
  const ElementThreads shared{3, &busy};
  EXPECT_EQ(shared.now(), 2);
  busy = false;
  EXPECT_EQ(shared.now(), 3);
  EXPECT_EQ(ElementThreads{}.now(), default_element_threads());
  EXPECT_THROW(for_each_chunk(ElementThreads{3, nullptr}, 100, [](int begin, int) {
                 if (begin > 0) throw std::runtime_error("element failed");
               }),
               std::runtime_error);
}

// The std::thread back-end on its own (element_thread_pool.h; for_each_chunk's when built with
// FLEXFRAME_ELEMENT_THREADS=std), in every build: each chunk once per loop, on up to that many
// threads, loop after loop (its workers sleep and wake between them); the first exception reaches
// the caller after the other chunks ran; a loop inside a chunk runs serially instead of waiting
// for the busy pool.
TEST(Assembly, StdThreadPoolRunsEveryChunkOnceAndPassesExceptions) {
  for (int chunks : {1, 2, 3, 7, 16}) {
    for (int loop = 0; loop < 50; ++loop) {
      std::vector<int> runs(chunks, 0);  // each slot written by its chunk only
      std::vector<std::thread::id> by(chunks);
      run_chunks_on_std_threads(chunks, [&](int c) {
        ++runs[c];
        by[c] = std::this_thread::get_id();
      });
      for (int c = 0; c < chunks; ++c) { ASSERT_EQ(runs[c], 1) << "chunk " << c << " of " << chunks; }
      std::sort(by.begin(), by.end());
      EXPECT_LE(std::unique(by.begin(), by.end()) - by.begin(), chunks);
    }
  }
  std::vector<std::atomic<int>> ran(5);
  EXPECT_THROW(run_chunks_on_std_threads(5,
                                         [&](int c) {
                                           ++ran[c];
                                           if (c % 2 == 1) throw std::runtime_error("element failed");
                                         }),
               std::runtime_error);
  for (int c = 0; c < 5; ++c) { EXPECT_EQ(ran[c], 1) << "chunk " << c; }
  std::vector<std::vector<int>> inner(4, std::vector<int>(3, 0));
  run_chunks_on_std_threads(4, [&](int c) { run_chunks_on_std_threads(3, [&](int d) { ++inner[c][d]; }); });
  for (const auto& row : inner) { EXPECT_EQ(row, std::vector<int>(3, 1)); }
}
