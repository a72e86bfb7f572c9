// Meshless parameterization of a disc patch: boundary on a convex polygon, the
// sparse system, its solution.
#include <pcl/surface/meshless/delaunay_2d.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <pcl/surface/meshless/parameterization.h>
#include <pcl/surface/meshless/weights.h>

#include "test_support.h"

#include <algorithm>
#include <chrono>
#include <future>
#include <mutex>
#include <cmath>
#include <numeric>
#include <random>

using namespace pcl::meshless;

namespace {

constexpr double pi = 3.14159265358979323846;

/** A planar patch: `rim` points on a regular polygon (the boundary loop,
  * counter-clockwise, listed first) around jittered grid points strictly inside. */
struct PlanarPatch
{
  Points3 points;
  std::vector<pcl::index_t> loop;
  std::vector<pcl::index_t> all;
};

PlanarPatch
planarPatch (int rim, int grid, std::uint32_t seed)
{
  PlanarPatch patch;
  for (int k = 0; k < rim; ++k) {
    const double a = 2.0 * pi * k / rim;
    patch.points.emplace_back (std::cos (a), std::sin (a), 0.0);
    patch.loop.push_back (k);
  }
  std::mt19937 random (seed);
  std::uniform_real_distribution<double> jitter (-0.3, 0.3);
  const double h = 2.0 / grid;
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j) {
      const Eigen::Vector3d p (-1.0 + (i + 0.5 + jitter (random)) * h,
                               -1.0 + (j + 0.5 + jitter (random)) * h, 0.0);
      if (p.norm () < 0.93)
        patch.points.push_back (p);
    }
  patch.all.resize (patch.points.size ());
  std::iota (patch.all.begin (), patch.all.end (), 0);
  return patch;
}

Weights
patchWeights (const Points3& points, WeightType type)
{
  const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
  const OrderedNeighbourhoods ordered = orderNeighbourhoods (points, graph);
  return computeWeights (points, ordered.rings, graph, ordered.normals, {type});
}

/** The patch's system with mean value weights, its loop at `uv`. */
MeshlessSystem
meanValueSystem (const PlanarPatch& patch, const Points2& uv)
{
  return buildMeshlessSystem (patchWeights (patch.points, WeightType::MeanValue), patch.all,
                              patch.loop, uv);
}

} // namespace

TEST (Parameterization, CircleBoundaryIsChordLengthCounterClockwise)
{
  const Points3 points = {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {0, 2, 0}};
  const std::vector<pcl::index_t> loop = {0, 1, 2, 3};
  const Points2 uv = circleBoundary (points, loop);
  ASSERT_EQ (uv.size (), 4u);
  const double expected[] = {0.0, 1.0 / 6.0, 3.0 / 6.0, 4.0 / 6.0}; // lengths 1, 2, 1, 2
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR (uv[k].norm (), 1.0, 1e-15);
    double a = std::atan2 (uv[k].y (), uv[k].x ());
    a = a < -1e-12 ? a + 2 * pi : a;
    EXPECT_NEAR (a, 2 * pi * expected[k], 1e-12);
  }
}

TEST (Parameterization, PolygonBoundaryPutsCornersOnCornersAndSidesOnSides)
{
  const Points3 points = {{0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {3, 1, 0}, {0, 1, 0}};
  const std::vector<pcl::index_t> loop = {0, 1, 2, 3, 4};
  const Points2 corners = {{0, 0}, {1, 0}, {0, 1}};
  const Points2 uv = polygonBoundary (points, loop, {0, 2, 3}, corners);
  ASSERT_EQ (uv.size (), 5u);
  EXPECT_TRUE (uv[0].isApprox (corners[0]));
  EXPECT_TRUE (uv[2].isApprox (corners[1]));
  EXPECT_TRUE (uv[3].isApprox (corners[2]));
  EXPECT_NEAR (uv[1].x (), 1.0 / 3.0, 1e-15); // 1 of 3 along the first side
  EXPECT_NEAR (uv[1].y (), 0.0, 1e-15);
  EXPECT_NEAR (uv[4].x (), 0.0, 1e-15);        // on the side from corner 2 to 0
  EXPECT_NEAR (uv[4].y (), 1.0 - 3.0 / 4.0, 1e-15);
  EXPECT_TRUE (polygonBoundary (points, loop, {0, 3, 2}, corners).empty ()) << "corners out of order";
  EXPECT_TRUE (polygonBoundary (points, loop, {0, 2, 3}, {{0, 0}, {0, 1}, {1, 0}}).empty ())
      << "clockwise polygon";
}

TEST (Parameterization, SystemIsAnMMatrixWithRowsSummingToTheBoundaryShare)
{
  const PlanarPatch patch = planarPatch (40, 30, 1);
  const Points2 uv = circleBoundary (patch.points, patch.loop);
  const MeshlessSystem system = meanValueSystem (patch, uv);
  ASSERT_TRUE (system.success) << system.message;
  ASSERT_EQ (static_cast<std::size_t> (system.matrix.rows ()), patch.points.size () - 40);
  for (Eigen::Index r = 0; r < system.matrix.outerSize (); ++r) {
    double row_sum = 0.0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it (system.matrix, r); it; ++it) {
      if (it.col () == r)
        EXPECT_DOUBLE_EQ (it.value (), 1.0);
      else
        EXPECT_LE (it.value (), 0.0);
      row_sum += it.value ();
    }
    EXPECT_GE (row_sum, -1e-12); // the weights on boundary neighbours
  }
}

TEST (Parameterization, LinearPrecisionOnAPlaneWithItsOwnBoundary)
{
  // The boundary mapped to its own planar positions: mean value and
  // shape-preserving weights reproduce every interior point, with both solvers.
  const PlanarPatch patch = planarPatch (48, 40, 2);
  Points2 own_boundary;
  for (auto b : patch.loop)
    own_boundary.push_back (patch.points[b].head<2> ());
  for (WeightType type : {WeightType::MeanValue, WeightType::ShapePreserving})
    for (SparseSolver solver : {SparseSolver::SparseLU, SparseSolver::BiCGSTAB}) {
      const Weights weights = patchWeights (patch.points, type);
      ASSERT_LE (weights.num_fallbacks, patch.loop.size ()) << "only rim points lack a star";
      const MeshlessSystem system =
          buildMeshlessSystem (weights, patch.all, patch.loop, own_boundary);
      ASSERT_TRUE (system.success) << system.message;
      SolveOptions options;
      options.solver = solver;
      const Parameterization result =
          solveMeshlessSystem (system, patch.all, patch.loop, own_boundary, options);
      ASSERT_TRUE (result.success) << result.message;
      for (std::size_t i = 0; i < patch.points.size (); ++i)
        EXPECT_LT ((result.uv[i] - patch.points[i].head<2> ()).norm (), 1e-9) << "point " << i;

      // ... so the triangulation of the parameter points is the planar Delaunay
      // triangulation of the points themselves.
      Points2 planar;
      for (const auto& p : patch.points)
        planar.push_back (p.head<2> ());
      auto canonical = [] (Triangles triangles) {
        for (auto& t : triangles)
          std::rotate (t.begin (), std::min_element (t.begin (), t.end ()), t.end ());
        std::sort (triangles.begin (), triangles.end ());
        return triangles;
      };
      const Delaunay2DResult from_map = delaunay2D (result.uv);
      const Delaunay2DResult from_plane = delaunay2D (planar);
      ASSERT_TRUE (from_map.success && from_plane.success);
      EXPECT_EQ (canonical (from_map.triangles), canonical (from_plane.triangles));
    }
}

TEST (Parameterization, SingleFactorsAreRefinedToDoublePrecision)
{
  // The direct solver factors in single precision (half the memory of the values)
  // and refines in double: the residual is that of double factors, not float's 1e-7.
  const PlanarPatch patch = planarPatch (48, 40, 6);
  const Points2 uv = circleBoundary (patch.points, patch.loop);
  const MeshlessSystem system = meanValueSystem (patch, uv);
  ASSERT_TRUE (system.success) << system.message;
  const Parameterization result = solveMeshlessSystem (system, patch.all, patch.loop, uv);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_LT (result.residual, 1e-13);
  EXPECT_FALSE (result.double_precision_factors);
  EXPECT_GE (result.iterations, 1) << "refinement steps";
}

TEST (Parameterization, TooIllConditionedForSingleFactorsIsSolvedInDouble)
{
  // Two interior points that lean on each other with weight 1 - 1e-9 and on the
  // boundary with 1e-9: rounded to single precision the matrix is singular; in
  // double its condition number is about 1e9 and the solution well defined (to a
  // relative residual of about 1e-7: the tolerance is loosened to that).
  const double share = 1e-9, lean = 1.0 - share;
  MeshlessSystem system;
  system.success = true;
  system.matrix.resize (2, 2);
  std::vector<Eigen::Triplet<double>> entries{{0, 0, 1.0}, {0, 1, -lean}, {1, 0, -lean}, {1, 1, 1.0}};
  system.matrix.setFromTriplets (entries.begin (), entries.end ());
  const Points2 uv{{1.0, 0.0}, {-0.5, 0.8}, {-0.5, -0.8}};
  system.rhs.resize (2, 2);
  system.rhs.row (0) = share * uv[0].transpose ();
  system.rhs.row (1) = share * uv[1].transpose ();
  system.interior = {3, 4};
  system.unknown_of = {-1, -1, -1, 0, 1};
  const std::vector<pcl::index_t> points{0, 1, 2, 3, 4}, loop{0, 1, 2};
  SolveOptions options;
  options.tolerance = 1e-6;
  const Parameterization result = solveMeshlessSystem (system, points, loop, uv, options);
  ASSERT_TRUE (result.success) << result.message;
  const Eigen::Matrix2d dense = Eigen::MatrixXd (system.matrix);
  const Eigen::MatrixX2d exact = dense.fullPivLu ().solve (system.rhs);
  EXPECT_LT ((result.uv[3] - exact.row (0).transpose ()).norm (), 1e-6);
  EXPECT_LT ((result.uv[4] - exact.row (1).transpose ()).norm (), 1e-6);
  EXPECT_LE (result.residual, 1e-6);
  EXPECT_TRUE (result.double_precision_factors);
}

TEST (Parameterization, LargeFactorizationsWaitForTheLock)
{
  const PlanarPatch patch = planarPatch (40, 30, 7);
  const Points2 uv = circleBoundary (patch.points, patch.loop);
  const MeshlessSystem system = meanValueSystem (patch, uv);
  ASSERT_TRUE (system.success) << system.message;
  std::mutex lock;
  SolveOptions options;
  options.factorization_lock = &lock;
  const auto solveAside = [&] () {
    return std::async (std::launch::async, [&] () {
      return solveMeshlessSystem (system, patch.all, patch.loop, uv, options);
    });
  };
  std::unique_lock<std::mutex> held (lock);
  // Below exclusive_from (the default 50,000 unknowns) the lock is not taken.
  auto small = solveAside ();
  ASSERT_EQ (small.wait_for (std::chrono::seconds (60)), std::future_status::ready);
  EXPECT_TRUE (small.get ().success);
  // At or above it the solve waits while another holds the lock ...
  options.exclusive_from = 1;
  auto large = solveAside ();
  EXPECT_EQ (large.wait_for (std::chrono::milliseconds (300)), std::future_status::timeout);
  // ... and goes on once it is free.
  held.unlock ();
  ASSERT_EQ (large.wait_for (std::chrono::seconds (60)), std::future_status::ready);
  EXPECT_TRUE (large.get ().success);
}

TEST (Parameterization, InteriorPointsLandStrictlyInsideTheCircle)
{
  const PlanarPatch patch = planarPatch (40, 30, 3);
  for (WeightType type : {WeightType::Uniform, WeightType::ReciprocalDistance}) {
    const Weights weights = patchWeights (patch.points, type);
    const Points2 uv = circleBoundary (patch.points, patch.loop);
    const MeshlessSystem system = buildMeshlessSystem (weights, patch.all, patch.loop, uv);
    const Parameterization result = solveMeshlessSystem (system, patch.all, patch.loop, uv);
    ASSERT_TRUE (result.success) << result.message;
    for (std::size_t i = 40; i < patch.points.size (); ++i)
      EXPECT_LT (result.uv[i].norm (), 1.0) << "point " << i;
  }
}

TEST (Parameterization, AnInteriorIslandWithoutAPathToTheBoundaryIsAnError)
{
  // Two interior points that only see each other: the system would be singular.
  PlanarPatch patch = planarPatch (12, 6, 4);
  Weights weights = patchWeights (patch.points, WeightType::Uniform);
  const pcl::index_t a = static_cast<pcl::index_t> (patch.points.size ());
  patch.points.emplace_back (5.0, 5.0, 0.0);
  patch.points.emplace_back (5.1, 5.0, 0.0);
  patch.all.push_back (a);
  patch.all.push_back (a + 1);
  weights.neighbours.adjacency.push_back (a + 1);
  weights.neighbours.offsets.push_back (static_cast<pcl::index_t> (weights.neighbours.adjacency.size ()));
  weights.neighbours.adjacency.push_back (a);
  weights.neighbours.offsets.push_back (static_cast<pcl::index_t> (weights.neighbours.adjacency.size ()));
  weights.values.push_back (1.0);
  weights.values.push_back (1.0);
  const Points2 uv = circleBoundary (patch.points, patch.loop);
  const MeshlessSystem system = buildMeshlessSystem (weights, patch.all, patch.loop, uv);
  EXPECT_FALSE (system.success);
  EXPECT_NE (system.message.find ("no path to its boundary"), std::string::npos) << system.message;
  const Parameterization result = solveMeshlessSystem (system, patch.all, patch.loop, uv);
  EXPECT_FALSE (result.success);
}

TEST (Parameterization, BadBoundaryInputIsAnError)
{
  const PlanarPatch patch = planarPatch (12, 6, 5);
  const Weights weights = patchWeights (patch.points, WeightType::Uniform);
  const Points2 uv = circleBoundary (patch.points, patch.loop);
  EXPECT_FALSE (buildMeshlessSystem (weights, patch.all, {0, 1}, {uv[0], uv[1]}).success);
  std::vector<pcl::index_t> repeated = patch.loop;
  repeated[3] = repeated[2];
  EXPECT_FALSE (buildMeshlessSystem (weights, patch.all, repeated, uv).success);
}
