/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <pcl/surface/meshless/parameterization.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseLU>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <unordered_map>

namespace pcl {
namespace meshless {

namespace {

constexpr double two_pi = 6.283185307179586476925286766559;

/** Lengths of the loop's edges (edge k joins loop[k] and loop[k+1]), with
  * zero-length edges lifted to a small share so that positions stay distinct. */
std::vector<double>
loopEdgeLengths (const Points3& points, const std::vector<pcl::index_t>& loop)
{
  const std::size_t m = loop.size ();
  std::vector<double> length (m);
  double total = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    length[k] = (points[loop[(k + 1) % m]] - points[loop[k]]).norm ();
    total += length[k];
  }
  const double floor_length = total > 0.0 ? 1e-3 * total / static_cast<double> (m) : 1.0;
  for (double& l : length)
    l = std::max (l, floor_length);
  return length;
}

/** The fill-reducing order of a patch's matrix: approximate minimum degree on the
  * pattern of A + A^T, as Eigen::AMDOrdering computes it (the same pattern, so the
  * same order), but from a pattern built here in float: AMDOrdering wants a
  * column-major copy of the matrix and adds its transpose in the matrix's scalar, a
  * passing 50 MB on a 180,000-point patch, which ran beside the factorization of
  * another patch and raised the peak memory of large clouds. */
void
fillReducingOrder (const Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix,
                   Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>& order)
{
  const auto n = static_cast<std::size_t> (matrix.rows ());
  const pcl::index_t* offsets = matrix.outerIndexPtr ();
  const pcl::index_t* inner = matrix.innerIndexPtr ();
  Eigen::SparseMatrix<float, Eigen::ColMajor, int> pattern (matrix.rows (), matrix.cols ());
  {
    // Column j of A + A^T: row j of A (stored) merged with column j of A (the rows
    // of the transpose), both sorted.
    const CsrGraph columns = transposeGraph (n, offsets, inner);
    std::vector<int> column_size (n);
    const auto mergeColumn = [&] (std::size_t j, auto&& emit) {
      const pcl::index_t *a = inner + offsets[j], *a_end = inner + offsets[j + 1];
      const pcl::index_t *b = columns.begin (static_cast<pcl::index_t> (j)),
                         *b_end = columns.end (static_cast<pcl::index_t> (j));
      while (a != a_end || b != b_end) {
        const pcl::index_t next = b == b_end || (a != a_end && *a < *b) ? *a : *b;
        emit (next);
        if (a != a_end && *a == next)
          ++a;
        if (b != b_end && *b == next)
          ++b;
      }
    };
    for (std::size_t j = 0; j < n; ++j) {
      int count = 0;
      mergeColumn (j, [&] (pcl::index_t) { ++count; });
      column_size[j] = count;
    }
    pattern.reserve (column_size);
    for (std::size_t j = 0; j < n; ++j)
      mergeColumn (j, [&] (pcl::index_t i) {
        pattern.insert (i, static_cast<Eigen::Index> (j)) = 0.0f;
      });
  }
  pattern.makeCompressed ();
  Eigen::internal::minimum_degree_ordering (pattern, order);
}

/** Solves system.matrix x = system.rhs with LU factors of the matrix permuted
  * symmetrically by `order`, computed in Scalar precision, then refines x
  * in double precision: x += A^-1 (b - A x) with the same factors while the
  * residual halves, until it is below 1e-13 of the right-hand side. Single
  * precision factors take two thirds of the memory of double ones (4 + 4 bytes per
  * nonzero instead of 8 + 4); with a condition number far below 1/epsilon each step
  * gains several digits: on the 1M armadillo's patches 1.5e-6 -> 4e-11 -> 3e-15
  * in two steps, the residual of double factors. Refining on to double rounding
  * took two more solves per patch for nothing (5.7e-14 -> 2.4e-15 -> 2.4e-15 on
  * its largest patch; 0.3 s of the chain of large factorizations on that cloud).
  * Returns false if the factorization failed (`problem` says why) or the residual
  * stalled above `target`. `steps` counts the refinement steps. */
template <typename Scalar>
bool
factorAndRefine (const MeshlessSystem& system,
                 const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>& order,
                 double target,
                 Eigen::MatrixX2d& solution,
                 int& steps,
                 std::string& problem)
{
  using Matrix2 = Eigen::Matrix<Scalar, Eigen::Dynamic, 2>;
  Eigen::SparseLU<Eigen::SparseMatrix<Scalar>, Eigen::NaturalOrdering<int>> lu;
  lu.isSymmetric (true);
  // A row swaps in only where the diagonal falls below 1% of its column.
  lu.setPivotThreshold (Scalar (0.01));
  const auto to_ordered = order.inverse ();
  {
    // Only the matrix in Scalar is left when the factorization starts (the copies
    // on the way count towards the peak of large clouds).
    Eigen::SparseMatrix<Scalar> factored;
    {
      const Eigen::SparseMatrix<double> column_major = system.matrix;
      Eigen::SparseMatrix<double> ordered;
      ordered = column_major.twistedBy (to_ordered);
      factored = ordered.template cast<Scalar> ();
    }
    lu.analyzePattern (factored);
    lu.factorize (factored);
  }
  if (lu.info () != Eigen::Success) {
    problem = "the sparse LU factorization failed: " + lu.lastErrorMessage ();
    return false;
  }
  const auto solve = [&] (const Eigen::MatrixX2d& rhs) -> Eigen::MatrixX2d {
    const Matrix2 ordered_rhs = (to_ordered * rhs).template cast<Scalar> ();
    const Matrix2 ordered_solution = lu.solve (ordered_rhs);
    return order * ordered_solution.template cast<double> ();
  };
  solution = solve (system.rhs);
  const double rhs_norm = std::max (system.rhs.norm (), 1e-300);
  double last = std::numeric_limits<double>::infinity ();
  steps = 0;
  for (; steps < 50; ++steps) {
    const Eigen::MatrixX2d residual = system.rhs - system.matrix * solution;
    const double relative = residual.norm () / rhs_norm;
    if (!(relative > 1e-13) || !(relative < 0.5 * last))
      return relative <= target;
    last = relative;
    solution += solve (residual);
  }
  return true; // the caller checks the residual
}

} // namespace

Points2
circleBoundary (const Points3& points, const std::vector<pcl::index_t>& loop)
{
  const std::size_t m = loop.size ();
  Points2 uv (m);
  if (m == 0)
    return uv;
  const std::vector<double> length = loopEdgeLengths (points, loop);
  double total = 0.0;
  for (double l : length)
    total += l;
  double walked = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const double angle = two_pi * walked / total;
    uv[k] = Eigen::Vector2d (std::cos (angle), std::sin (angle));
    walked += length[k];
  }
  return uv;
}

Points2
polygonBoundary (const Points3& points,
                 const std::vector<pcl::index_t>& loop,
                 const std::vector<std::size_t>& corner_positions,
                 const Points2& corners)
{
  const std::size_t m = loop.size ();
  const std::size_t c = corners.size ();
  if (c < 3 || corner_positions.size () != c || m < c)
    return {};
  for (std::size_t i = 0; i < c; ++i) {
    if (corner_positions[i] >= m || (i > 0 && corner_positions[i] <= corner_positions[i - 1]))
      return {};
    const Eigen::Vector2d e0 = corners[(i + 1) % c] - corners[i];
    const Eigen::Vector2d e1 = corners[(i + 2) % c] - corners[(i + 1) % c];
    if (!(e0.x () * e1.y () - e0.y () * e1.x () > 0.0))
      return {}; // not strictly convex, counter-clockwise
  }
  const std::vector<double> length = loopEdgeLengths (points, loop);
  Points2 uv (m);
  for (std::size_t i = 0; i < c; ++i) {
    // Side i runs from corner i to corner i+1 over loop positions
    // corner_positions[i] .. corner_positions[i+1] (cyclically).
    const std::size_t first = corner_positions[i];
    const std::size_t last = corner_positions[(i + 1) % c] + (i + 1 == c ? m : 0);
    double side = 0.0;
    for (std::size_t k = first; k < last; ++k)
      side += length[k % m];
    double walked = 0.0;
    for (std::size_t k = first; k < last; ++k) {
      const double t = walked / side;
      uv[k % m] = (1.0 - t) * corners[i] + t * corners[(i + 1) % c];
      walked += length[k % m];
    }
  }
  return uv;
}

MeshlessSystem
buildMeshlessSystem (const Weights& weights,
                     const std::vector<pcl::index_t>& patch_points,
                     const std::vector<pcl::index_t>& boundary_loop,
                     const Points2& boundary_uv,
                     const PatchRingContext* rings)
{
  MeshlessSystem system;
  const std::size_t m = patch_points.size ();
  if (boundary_loop.size () < 3 || boundary_uv.size () != boundary_loop.size ()) {
    system.message = "a patch needs a boundary loop of at least three points, each with "
                     "a parameter position";
    return system;
  }

  // Patch-local numbering, an array over the cloud: a hash map of the patch's
  // points took 0.1 s of the largest patch of a million points (and 11 MB), before
  // its factorization could start; filling 4 bytes per cloud point per patch costs
  // a millisecond per million points.
  const std::size_t n = weights.neighbours.size ();
  std::vector<pcl::index_t> local_at (n, -1);
  for (std::size_t i = 0; i < m; ++i) {
    const pcl::index_t v = patch_points[i];
    if (v < 0 || static_cast<std::size_t> (v) >= n) {
      system.message = "a patch point is not a point of the weights";
      return system;
    }
    if (local_at[v] >= 0) {
      system.message = "a point is listed twice in the patch";
      return system;
    }
    local_at[v] = static_cast<pcl::index_t> (i);
  }
  const auto inPatch = [&] (pcl::index_t w) { return local_at[w] >= 0; };
  std::vector<pcl::index_t> boundary_slot (m, -1); // position in the boundary loop
  for (std::size_t k = 0; k < boundary_loop.size (); ++k) {
    const pcl::index_t v = boundary_loop[k];
    const pcl::index_t local = v >= 0 && static_cast<std::size_t> (v) < n ? local_at[v] : -1;
    if (local < 0 || boundary_slot[local] >= 0) {
      system.message = "a boundary point is missing from the patch or repeated in the loop";
      return system;
    }
    boundary_slot[local] = static_cast<pcl::index_t> (k);
  }

  system.unknown_of.assign (m, -1);
  for (std::size_t i = 0; i < m; ++i)
    if (boundary_slot[i] < 0) {
      system.unknown_of[i] = static_cast<pcl::index_t> (system.interior.size ());
      system.interior.push_back (static_cast<pcl::index_t> (i));
    }
  const std::size_t unknowns = system.interior.size ();

  // Rows: u_i - sum lambda_ij u_j (interior j) = sum lambda_ij u_j (boundary j), the
  // weights restricted to the patch and renormalised to sum to one.
  // Filled row by row in place (no triplet list: 16 bytes per entry, 40 MB on the
  // largest patch of a million points, alive while another patch factorizes).
  system.matrix.resize (static_cast<Eigen::Index> (unknowns), static_cast<Eigen::Index> (unknowns));
  system.matrix.reserve (static_cast<Eigen::Index> (unknowns * 8));
  std::vector<std::pair<pcl::index_t, double>> row_entries;
  system.rhs = Eigen::MatrixX2d::Zero (static_cast<Eigen::Index> (unknowns), 2);
  std::vector<char> touches_boundary (unknowns, 0); // a weight on a boundary point
  std::vector<pcl::index_t> row_points, inside_candidates;
  std::vector<double> row_weights;
  Points2 local_ring;
  std::vector<int> ring;
  for (std::size_t row = 0; row < unknowns; ++row) {
    const pcl::index_t local = system.interior[row];
    const pcl::index_t v = patch_points[local];
    // This point's weights, restricted to the patch.
    row_points.clear ();
    row_weights.clear ();
    bool reaches_out = false;
    for (auto k = weights.neighbours.offsets[v]; k < weights.neighbours.offsets[v + 1]; ++k) {
      const pcl::index_t w = weights.neighbours.adjacency[k];
      if (inPatch (w)) {
        row_points.push_back (w);
        row_weights.push_back (weights.values[k]);
      }
      else
        reaches_out = true;
    }
    if (reaches_out && rings && rings->points && rings->candidates && rings->normals) {
      // The point's own ring among its candidates inside the patch.
      inside_candidates.clear ();
      for (const pcl::index_t* w = rings->candidates->begin (v); w != rings->candidates->end (v); ++w)
        if (inPatch (*w))
          inside_candidates.push_back (*w);
      localCoordinates (*rings->points, v, inside_candidates.data (),
                        inside_candidates.data () + inside_candidates.size (),
                        (*rings->normals)[v].cast<double> (), rings->weights.plane, local_ring);
      delaunayRing (local_ring, ring);
      Points2 ordered_ring;
      for (int r : ring)
        ordered_ring.push_back (local_ring[r]);
      std::vector<double> lambda;
      const bool mean_value = rings->weights.type == WeightType::MeanValue;
      if ((mean_value || rings->weights.type == WeightType::ShapePreserving) &&
          (mean_value ? meanValueWeights (ordered_ring, lambda)
                      : shapePreservingWeights (ordered_ring, lambda))) {
        row_points.clear ();
        for (int r : ring)
          row_points.push_back (inside_candidates[r]);
        row_weights = std::move (lambda);
        ++system.num_rerung;
      }
    }
    double inside = 0.0;
    for (double lambda : row_weights)
      inside += lambda;
    if (!(inside > 0.0)) {
      system.message = "an interior point of the patch has no neighbour inside the patch "
                       "(increase the number of neighbours k or the radius)";
      return system;
    }
    row_entries.clear ();
    row_entries.emplace_back (static_cast<pcl::index_t> (row), 1.0);
    for (std::size_t j = 0; j < row_points.size (); ++j) {
      const double lambda = row_weights[j] / inside;
      const pcl::index_t w = local_at[row_points[j]];
      if (lambda == 0.0 || w == local)
        continue;
      if (boundary_slot[w] >= 0) {
        system.rhs.row (row) += lambda * boundary_uv[boundary_slot[w]].transpose ();
        touches_boundary[row] = 1;
      }
      else
        row_entries.emplace_back (system.unknown_of[w], -lambda);
    }
    // Columns ascending, repeated ones summed (as setFromTriplets would).
    std::stable_sort (row_entries.begin (), row_entries.end (),
               [] (const auto& a, const auto& b) { return a.first < b.first; });
    std::size_t kept = 0;
    for (std::size_t j = 0; j < row_entries.size (); ++j)
      if (kept > 0 && row_entries[j].first == row_entries[kept - 1].first)
        row_entries[kept - 1].second += row_entries[j].second;
      else
        row_entries[kept++] = row_entries[j];
    system.matrix.startVec (static_cast<Eigen::Index> (row));
    for (std::size_t j = 0; j < kept; ++j)
      system.matrix.insertBack (static_cast<Eigen::Index> (row), row_entries[j].first) =
          row_entries[j].second;
  }
  system.matrix.finalize ();

  // Non-singular iff every interior point reaches the boundary along directed
  // weight edges. Search backwards from the rows with a boundary weight; column j
  // of the matrix lists the rows that depend on unknown j.
  // (The column lists hold row numbers only: a third of a column-major copy.)
  static_assert (std::is_same<Eigen::SparseMatrix<double>::StorageIndex, pcl::index_t>::value,
                 "the matrix's indices read as a graph");
  const CsrGraph dependents = transposeGraph (unknowns, system.matrix.outerIndexPtr (),
                                              system.matrix.innerIndexPtr ());
  std::vector<char> reaches (touches_boundary);
  std::vector<pcl::index_t> stack;
  for (std::size_t row = 0; row < unknowns; ++row)
    if (reaches[row])
      stack.push_back (static_cast<pcl::index_t> (row));
  while (!stack.empty ()) {
    const pcl::index_t j = stack.back ();
    stack.pop_back ();
    for (const pcl::index_t* row = dependents.begin (j); row != dependents.end (j); ++row)
      if (!reaches[*row]) {
        reaches[*row] = 1;
        stack.push_back (*row);
      }
  }
  std::size_t cut_off = 0;
  for (char r : reaches)
    cut_off += !r;
  if (cut_off > 0) {
    system.message = std::to_string (cut_off) +
                     " interior point(s) of the patch have no path to its boundary (the "
                     "patch is disconnected; increase k or the radius)";
    return system;
  }
  system.success = true;
  return system;
}

Parameterization
solveMeshlessSystem (const MeshlessSystem& system,
                     const std::vector<pcl::index_t>& patch_points,
                     const std::vector<pcl::index_t>& boundary_loop,
                     const Points2& boundary_uv,
                     const SolveOptions& options)
{
  Parameterization result;
  if (!system.success) {
    result.message = "the system was not built: " + system.message;
    return result;
  }
  // The boundary's parameter points, placed after the solve: the map from point to
  // patch position would otherwise live through the factorization.
  const auto placeBoundary = [&] () {
    const std::size_t m = patch_points.size ();
    result.uv.assign (m, Eigen::Vector2d::Zero ());
    std::unordered_map<pcl::index_t, pcl::index_t> local_of;
    for (std::size_t i = 0; i < m; ++i)
      local_of.emplace (patch_points[i], static_cast<pcl::index_t> (i));
    for (std::size_t k = 0; k < boundary_loop.size (); ++k)
      result.uv[local_of.at (boundary_loop[k])] = boundary_uv[k];
  };

  const Eigen::Index unknowns = system.matrix.rows ();
  if (unknowns == 0) {
    placeBoundary ();
    result.success = true;
    return result;
  }
  Eigen::MatrixX2d solution;
  if (options.solver == SparseSolver::SparseLU) {
    // The matrix is I - W with W's rows convex: diagonally dominant by rows, so
    // elimination on the diagonal is stable and the rows need no pivoting. Ordered
    // symmetrically by AMD on the pattern of A + A^T (SparseLU's own orderings
    // permute columns only, which moves the diagonal off and makes it pivot), the
    // factors fill far less: on a 205,102-unknown patch of the 1M armadillo, L + U
    // 27.7M -> 11.3M nonzeros, 1.58 -> 0.54 s, with the same residual (3e-15).
    // The factors are computed in single precision and the solution refined in
    // double (see factorAndRefine): they set the peak memory of large clouds.
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
    fillReducingOrder (system.matrix, order);
    const double target = std::max (options.tolerance, 1e-8);
    std::unique_lock<std::mutex> exclusive;
    if (options.factorization_lock && static_cast<std::size_t> (unknowns) >= options.exclusive_from)
      exclusive = std::unique_lock<std::mutex> (*options.factorization_lock);
    std::string problem;
    if (!factorAndRefine<float> (system, order, target, solution, result.iterations,
                                 problem)) {
      // A matrix too ill-conditioned for single precision (never seen on real
      // clouds) stalls the refinement or is singular when rounded: double factors.
      problem.clear ();
      result.double_precision_factors = true;
      factorAndRefine<double> (system, order, target, solution, result.iterations,
                               problem);
    }
    if (!problem.empty ()) {
      result.message = problem;
      return result;
    }
  }
  else {
    Eigen::SparseMatrix<double> column_major = system.matrix;
    Eigen::BiCGSTAB<Eigen::SparseMatrix<double>, Eigen::IncompleteLUT<double>> bicg;
    bicg.setTolerance (options.tolerance);
    bicg.setMaxIterations (options.max_iterations);
    bicg.compute (column_major);
    if (bicg.info () != Eigen::Success) {
      result.message = "the incomplete LU preconditioner could not be computed";
      return result;
    }
    solution.resize (unknowns, 2);
    for (int c = 0; c < 2; ++c) {
      solution.col (c) = bicg.solve (system.rhs.col (c));
      result.iterations = std::max (result.iterations, static_cast<int> (bicg.iterations ()));
      if (bicg.info () != Eigen::Success) {
        result.message = "BiCGSTAB did not converge within " +
                         std::to_string (options.max_iterations) + " iterations";
        return result;
      }
    }
  }
  if (!solution.allFinite ()) {
    result.message = "the parameterization has non-finite parameter points (singular system)";
    return result;
  }
  const double rhs_norm = std::max (system.rhs.norm (), 1e-300);
  result.residual = (system.matrix * solution - system.rhs).norm () / rhs_norm;
  if (!(result.residual <= std::max (options.tolerance, 1e-8))) {
    result.message = "the parameterization's residual " + std::to_string (result.residual) +
                     " is too large (ill-conditioned system)";
    return result;
  }
  placeBoundary ();
  for (Eigen::Index row = 0; row < unknowns; ++row)
    result.uv[system.interior[row]] = solution.row (row).transpose ();
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
