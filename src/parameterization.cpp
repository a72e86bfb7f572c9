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
  * column-major copy of the matrix and adds its transpose in the matrix's scalar,
  * a passing copy that runs beside the factorization of another patch and raises
  * the peak memory of large clouds. */
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
  * gains several digits, and two steps reach the residual of double factors.
  * Refining on to double rounding would cost more solves and gain nothing.
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

namespace {

/** Builds the linear system of one patch (see buildMeshlessSystem): numbers the
  * patch's points, fills one row per interior point, checks that the matrix is
  * non-singular. */
class MeshlessSystemBuilder
{
public:
  MeshlessSystemBuilder (const Weights& weights,
                         const std::vector<pcl::index_t>& patch_points,
                         const std::vector<pcl::index_t>& boundary_loop,
                         const Points2& boundary_uv,
                         const PatchRingContext* rings)
  : weights_ (weights)
  , patch_points_ (patch_points)
  , boundary_loop_ (boundary_loop)
  , boundary_uv_ (boundary_uv)
  , rings_ (rings)
  {}

  MeshlessSystem
  build ()
  {
    if (boundary_loop_.size () < 3 || boundary_uv_.size () != boundary_loop_.size ()) {
      system_.message = "a patch needs a boundary loop of at least three points, each with "
                        "a parameter position";
      return std::move (system_);
    }
    if (!numberPatchPoints () || !findBoundarySlots ())
      return std::move (system_);
    numberUnknowns ();
    if (!fillRows () || !checkBoundaryReached ())
      return std::move (system_);
    system_.success = true;
    return std::move (system_);
  }

private:
  /** Patch-local numbering, an array over the cloud: a hash map of the patch's
    * points took a noticeable share of the largest patches' time (and memory)
    * before their factorization could start; filling 4 bytes per cloud point per
    * patch costs next to nothing. \return false (the message set) on a point
    * outside the weights or listed twice. */
  bool
  numberPatchPoints ()
  {
    const std::size_t n = weights_.neighbours.size ();
    local_at_.assign (n, -1);
    for (std::size_t i = 0; i < patch_points_.size (); ++i) {
      const pcl::index_t v = patch_points_[i];
      if (v < 0 || static_cast<std::size_t> (v) >= n) {
        system_.message = "a patch point is not a point of the weights";
        return false;
      }
      if (local_at_[v] >= 0) {
        system_.message = "a point is listed twice in the patch";
        return false;
      }
      local_at_[v] = static_cast<pcl::index_t> (i);
    }
    return true;
  }

  bool
  inPatch (pcl::index_t w) const
  {
    return local_at_[w] >= 0;
  }

  /** Per patch point: its position in the boundary loop, or -1. \return false (the
    * message set) if a loop point is not in the patch or repeated. */
  bool
  findBoundarySlots ()
  {
    const std::size_t n = local_at_.size ();
    boundary_slot_.assign (patch_points_.size (), -1);
    for (std::size_t k = 0; k < boundary_loop_.size (); ++k) {
      const pcl::index_t v = boundary_loop_[k];
      const pcl::index_t local = v >= 0 && static_cast<std::size_t> (v) < n ? local_at_[v] : -1;
      if (local < 0 || boundary_slot_[local] >= 0) {
        system_.message = "a boundary point is missing from the patch or repeated in the loop";
        return false;
      }
      boundary_slot_[local] = static_cast<pcl::index_t> (k);
    }
    return true;
  }

  /** One unknown per interior point, in patch order. */
  void
  numberUnknowns ()
  {
    const std::size_t m = patch_points_.size ();
    system_.unknown_of.assign (m, -1);
    for (std::size_t i = 0; i < m; ++i)
      if (boundary_slot_[i] < 0) {
        system_.unknown_of[i] = static_cast<pcl::index_t> (system_.interior.size ());
        system_.interior.push_back (static_cast<pcl::index_t> (i));
      }
  }

  /** Rows: u_i - sum lambda_ij u_j (interior j) = sum lambda_ij u_j (boundary j), the
    * weights restricted to the patch and renormalised to sum to one. Filled row by
    * row in place: a triplet list (16 bytes per entry) would be alive while another
    * patch factorizes. \return false (the message set) on a row without weights. */
  bool
  fillRows ()
  {
    const std::size_t unknowns = system_.interior.size ();
    system_.matrix.resize (static_cast<Eigen::Index> (unknowns),
                           static_cast<Eigen::Index> (unknowns));
    system_.matrix.reserve (static_cast<Eigen::Index> (unknowns * 8));
    system_.rhs = Eigen::MatrixX2d::Zero (static_cast<Eigen::Index> (unknowns), 2);
    touches_boundary_.assign (unknowns, 0);
    for (std::size_t row = 0; row < unknowns; ++row) {
      const pcl::index_t v = patch_points_[system_.interior[row]];
      const bool reaches_out = restrictWeights (v);
      if (reaches_out && rings_ && rings_->points && rings_->candidates && rings_->normals)
        ringInsidePatch (v);
      if (!addRow (row)) {
        system_.message = "an interior point of the patch has no neighbour inside the patch "
                          "(increase the number of neighbours k or the radius)";
        return false;
      }
    }
    system_.matrix.finalize ();
    return true;
  }

  /** Point v's weights, restricted to the patch, into row_points_/row_weights_.
    * \return whether some of its weights lie outside the patch. */
  bool
  restrictWeights (pcl::index_t v)
  {
    row_points_.clear ();
    row_weights_.clear ();
    bool reaches_out = false;
    const CsrGraph& neighbours = weights_.neighbours;
    for (auto k = neighbours.offsets[v]; k < neighbours.offsets[v + 1]; ++k) {
      const pcl::index_t w = neighbours.adjacency[k];
      if (inPatch (w)) {
        row_points_.push_back (w);
        row_weights_.push_back (weights_.values[k]);
      }
      else
        reaches_out = true;
    }
    return reaches_out;
  }

  /** Point v's own ring among its candidates inside the patch, and its weights
    * there, replace the restricted ones (see PatchRingContext) where the weight
    * type can be recomputed and succeeds. */
  void
  ringInsidePatch (pcl::index_t v)
  {
    inside_candidates_.clear ();
    for (const pcl::index_t* w = rings_->candidates->begin (v); w != rings_->candidates->end (v);
         ++w)
      if (inPatch (*w))
        inside_candidates_.push_back (*w);
    localCoordinates (*rings_->points, v, inside_candidates_.data (),
                      inside_candidates_.data () + inside_candidates_.size (),
                      (*rings_->normals)[v].cast<double> (), rings_->weights.plane, local_ring_);
    delaunayRing (local_ring_, ring_);
    Points2 ordered_ring;
    for (int r : ring_)
      ordered_ring.push_back (local_ring_[r]);
    std::vector<double> lambda;
    const bool mean_value = rings_->weights.type == WeightType::MeanValue;
    if ((mean_value || rings_->weights.type == WeightType::ShapePreserving) &&
        (mean_value ? meanValueWeights (ordered_ring, lambda)
                    : shapePreservingWeights (ordered_ring, lambda))) {
      row_points_.clear ();
      for (int r : ring_)
        row_points_.push_back (inside_candidates_[r]);
      row_weights_ = std::move (lambda);
      ++system_.num_rerung;
    }
  }

  /** Row `row` from row_points_/row_weights_, renormalised; boundary neighbours go
    * to the right-hand side. \return false if the weights inside sum to zero. */
  bool
  addRow (std::size_t row)
  {
    double inside = 0.0;
    for (double lambda : row_weights_)
      inside += lambda;
    if (!(inside > 0.0))
      return false;
    const pcl::index_t local = system_.interior[row];
    row_entries_.clear ();
    row_entries_.emplace_back (static_cast<pcl::index_t> (row), 1.0);
    for (std::size_t j = 0; j < row_points_.size (); ++j) {
      const double lambda = row_weights_[j] / inside;
      const pcl::index_t w = local_at_[row_points_[j]];
      if (lambda == 0.0 || w == local)
        continue;
      if (boundary_slot_[w] >= 0) {
        system_.rhs.row (row) += lambda * boundary_uv_[boundary_slot_[w]].transpose ();
        touches_boundary_[row] = 1;
      }
      else
        row_entries_.emplace_back (system_.unknown_of[w], -lambda);
    }
    insertRow (row);
    return true;
  }

  /** row_entries_ into the matrix, columns ascending, repeated ones summed (as
    * setFromTriplets would). */
  void
  insertRow (std::size_t row)
  {
    std::stable_sort (row_entries_.begin (), row_entries_.end (),
                      [] (const auto& a, const auto& b) { return a.first < b.first; });
    std::size_t kept = 0;
    for (std::size_t j = 0; j < row_entries_.size (); ++j)
      if (kept > 0 && row_entries_[j].first == row_entries_[kept - 1].first)
        row_entries_[kept - 1].second += row_entries_[j].second;
      else
        row_entries_[kept++] = row_entries_[j];
    system_.matrix.startVec (static_cast<Eigen::Index> (row));
    for (std::size_t j = 0; j < kept; ++j)
      system_.matrix.insertBack (static_cast<Eigen::Index> (row), row_entries_[j].first) =
          row_entries_[j].second;
  }

  /** Non-singular iff every interior point reaches the boundary along directed
    * weight edges. Search backwards from the rows with a boundary weight; column j
    * of the matrix lists the rows that depend on unknown j (held as row numbers
    * only: a third of a column-major copy). \return false (the message set) if
    * some interior point does not reach it. */
  bool
  checkBoundaryReached ()
  {
    static_assert (std::is_same<Eigen::SparseMatrix<double>::StorageIndex, pcl::index_t>::value,
                   "the matrix's indices read as a graph");
    const std::size_t unknowns = system_.interior.size ();
    const CsrGraph dependents = transposeGraph (unknowns, system_.matrix.outerIndexPtr (),
                                                system_.matrix.innerIndexPtr ());
    std::vector<char> reaches (touches_boundary_);
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
      system_.message = std::to_string (cut_off) +
                        " interior point(s) of the patch have no path to its boundary (the "
                        "patch is disconnected; increase k or the radius)";
      return false;
    }
    return true;
  }

  const Weights& weights_;
  const std::vector<pcl::index_t>& patch_points_;
  const std::vector<pcl::index_t>& boundary_loop_;
  const Points2& boundary_uv_;
  const PatchRingContext* rings_;
  MeshlessSystem system_;
  /** Per cloud point: its position in the patch, or -1. */
  std::vector<pcl::index_t> local_at_;
  /** Per patch point: its position in the boundary loop, or -1. */
  std::vector<pcl::index_t> boundary_slot_;
  /** Per unknown: whether its row has a weight on a boundary point. */
  std::vector<char> touches_boundary_;
  // Scratch of one row.
  std::vector<pcl::index_t> row_points_, inside_candidates_;
  std::vector<double> row_weights_;
  std::vector<std::pair<pcl::index_t, double>> row_entries_;
  Points2 local_ring_;
  std::vector<int> ring_;
};

} // namespace

MeshlessSystem
buildMeshlessSystem (const Weights& weights,
                     const std::vector<pcl::index_t>& patch_points,
                     const std::vector<pcl::index_t>& boundary_loop,
                     const Points2& boundary_uv,
                     const PatchRingContext* rings)
{
  return MeshlessSystemBuilder (weights, patch_points, boundary_loop, boundary_uv, rings).build ();
}

namespace {

/** One parameter point per patch point, the boundary's placed, the interior's
  * zero. Placed after the solve: the map from point to patch position would
  * otherwise live through the factorization. */
void
placeBoundary (const std::vector<pcl::index_t>& patch_points,
               const std::vector<pcl::index_t>& boundary_loop,
               const Points2& boundary_uv,
               Points2& uv)
{
  const std::size_t m = patch_points.size ();
  uv.assign (m, Eigen::Vector2d::Zero ());
  std::unordered_map<pcl::index_t, pcl::index_t> local_of;
  for (std::size_t i = 0; i < m; ++i)
    local_of.emplace (patch_points[i], static_cast<pcl::index_t> (i));
  for (std::size_t k = 0; k < boundary_loop.size (); ++k)
    uv[local_of.at (boundary_loop[k])] = boundary_uv[k];
}

/** The direct solve. The matrix is I - W with W's rows convex: diagonally dominant
  * by rows, so elimination on the diagonal is stable and the rows need no pivoting.
  * Ordered symmetrically by AMD on the pattern of A + A^T (SparseLU's own orderings
  * permute columns only, which moves the diagonal off and makes it pivot), the
  * factors fill far less and are made faster, with the same residual. The factors
  * are computed in single precision and the solution refined in double (see
  * factorAndRefine): they set the peak memory of large clouds.
  * \return false (result's message set) if the factorization failed. */
bool
solveDirect (const MeshlessSystem& system,
             const SolveOptions& options,
             Eigen::MatrixX2d& solution,
             Parameterization& result)
{
  const auto unknowns = static_cast<std::size_t> (system.matrix.rows ());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
  fillReducingOrder (system.matrix, order);
  const double target = std::max (options.tolerance, 1e-8);
  std::unique_lock<std::mutex> exclusive;
  if (options.factorization_lock && unknowns >= options.exclusive_from)
    exclusive = std::unique_lock<std::mutex> (*options.factorization_lock);
  std::string problem;
  if (!factorAndRefine<float> (system, order, target, solution, result.iterations, problem)) {
    // A matrix too ill-conditioned for single precision (never seen on real
    // clouds) stalls the refinement or is singular when rounded: double factors.
    problem.clear ();
    result.double_precision_factors = true;
    factorAndRefine<double> (system, order, target, solution, result.iterations, problem);
  }
  if (!problem.empty ()) {
    result.message = problem;
    return false;
  }
  return true;
}

/** The iterative solve: BiCGSTAB preconditioned by an incomplete LU, one
  * coordinate at a time. \return false (result's message set) if it fails. */
bool
solveIterative (const MeshlessSystem& system,
                const SolveOptions& options,
                Eigen::MatrixX2d& solution,
                Parameterization& result)
{
  Eigen::SparseMatrix<double> column_major = system.matrix;
  Eigen::BiCGSTAB<Eigen::SparseMatrix<double>, Eigen::IncompleteLUT<double>> bicg;
  bicg.setTolerance (options.tolerance);
  bicg.setMaxIterations (options.max_iterations);
  bicg.compute (column_major);
  if (bicg.info () != Eigen::Success) {
    result.message = "the incomplete LU preconditioner could not be computed";
    return false;
  }
  solution.resize (system.matrix.rows (), 2);
  for (int c = 0; c < 2; ++c) {
    solution.col (c) = bicg.solve (system.rhs.col (c));
    result.iterations = std::max (result.iterations, static_cast<int> (bicg.iterations ()));
    if (bicg.info () != Eigen::Success) {
      result.message = "BiCGSTAB did not converge within " +
                       std::to_string (options.max_iterations) + " iterations";
      return false;
    }
  }
  return true;
}

} // namespace

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
  const Eigen::Index unknowns = system.matrix.rows ();
  if (unknowns == 0) {
    placeBoundary (patch_points, boundary_loop, boundary_uv, result.uv);
    result.success = true;
    return result;
  }
  Eigen::MatrixX2d solution;
  const bool solved = options.solver == SparseSolver::SparseLU
                          ? solveDirect (system, options, solution, result)
                          : solveIterative (system, options, solution, result);
  if (!solved)
    return result;
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
  placeBoundary (patch_points, boundary_loop, boundary_uv, result.uv);
  for (Eigen::Index row = 0; row < unknowns; ++row)
    result.uv[system.interior[row]] = solution.row (row).transpose ();
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
