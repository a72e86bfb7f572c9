/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>
#include <pcl/surface/meshless/weights.h>

#include <Eigen/SparseCore>

#include <mutex>

namespace pcl {
namespace meshless {

/** \brief Chord-length positions of a closed boundary loop on the unit circle:
  * t_k = (length of the loop up to point k) / (length of the loop),
  * u_k = (cos 2 pi t_k, sin 2 pi t_k), counter-clockwise in loop order.
  * Every point then lies on the convex hull of all parameter points, so consecutive
  * boundary points are joined by Delaunay edges.
  * \param[in] loop point indices in cyclic order (the last joins the first)
  * \note zero-length loop edges get a small share of the circle (a fraction of the
  *       mean edge length) so that no two boundary points coincide.
  */
Points2
circleBoundary (const Points3& points, const std::vector<pcl::index_t>& loop);

/** \brief Positions of a boundary loop on a convex polygon: the loop points at
  * `corner_positions[c]` (positions into `loop`, increasing) go to the polygon's
  * corners, the points between two corners go onto that side by chord length.
  * \param[in] corners the polygon's corners, counter-clockwise, strictly convex
  * \return one position per loop point, or an empty array if the corner data is
  *         inconsistent (sizes, order, fewer than three corners)
  * \note points on a straight side are collinear; the exact Delaunay stage keeps
  *       every one of them as a hull vertex, so the chain still appears as edges.
  */
Points2
polygonBoundary (const Points3& points,
                 const std::vector<pcl::index_t>& loop,
                 const std::vector<std::size_t>& corner_positions,
                 const Points2& corners);

/** \brief The linear system of the meshless parameterization of one patch:
  * u_i - sum_{j interior} lambda_ij u_j = sum_{j boundary} lambda_ij u_j
  * for every interior point i, weights restricted to the patch and renormalised. */
struct MeshlessSystem : StageStatus
{
  /** \brief I - Lambda over the interior points (a non-symmetric M-matrix). */
  Eigen::SparseMatrix<double, Eigen::RowMajor> matrix;
  /** \brief Two right-hand sides (u and v), one row per interior point. */
  Eigen::MatrixX2d rhs;
  /** \brief Interior points whose ring was recomputed inside the patch. */
  std::size_t num_rerung = 0;
  /** \brief Patch point position (into patch_points) of each unknown. */
  std::vector<pcl::index_t> interior;
  /** \brief Per patch point: its unknown's row, or -1 for boundary points. */
  std::vector<pcl::index_t> unknown_of;
};

/** \brief What a patch needs to give its points next to a cut their own rings.
  *
  * A point next to a path has ring neighbours on the far side, in another patch.
  * Dropping them and renormalising the rest biases the point away from the path
  * (its weights lose linear precision), and the triangles along the seam come out
  * tall and slanted on both sides, where they fold into each other. With this
  * context such a point's Delaunay ring and weights are recomputed among its
  * candidates inside the patch (the path points included), as if the patch were
  * the whole cloud. */
struct PatchRingContext
{
  const Points3* points = nullptr;
  /** \brief Candidate neighbours of every point (the graph G). */
  const CsrGraph* candidates = nullptr;
  /** \brief Oriented normals the rings are computed around. */
  const std::vector<Eigen::Vector3f>* normals = nullptr;
  WeightOptions weights;
};

/** \brief Build the system of one patch.
  * \param[in] weights weights of all points (global numbering)
  * \param[in] patch_points the patch's points (global indices), each once; the
  *            boundary loop's points must be among them
  * \param[in] boundary_loop the boundary in cyclic order (global indices)
  * \param[in] boundary_uv parameter position of each boundary loop point
  * \param[in] rings optional: recompute rings and weights inside the patch for
  *            points whose weights reach outside it (see PatchRingContext);
  *            without it, their weights are restricted and renormalised
  * \return fails if an interior point has no neighbour inside the patch, or no
  *         directed path to the boundary (the system would be singular)
  */
MeshlessSystem
buildMeshlessSystem (const Weights& weights,
                     const std::vector<pcl::index_t>& patch_points,
                     const std::vector<pcl::index_t>& boundary_loop,
                     const Points2& boundary_uv,
                     const PatchRingContext* rings = nullptr);

enum class SparseSolver
{
  /** Eigen::SparseLU on the matrix ordered symmetrically by AMD (on the pattern
    * of A + A^T), diagonal pivots preferred: direct, robust, default. */
  SparseLU,
  /** Eigen::BiCGSTAB with an incomplete LU (ILUT) preconditioner. */
  BiCGSTAB
};

struct SolveOptions
{
  /** \brief Default: SparseSolver::SparseLU (direct; faster and more robust than
    * the iterative solver on these systems). */
  SparseSolver solver = SparseSolver::SparseLU;
  /** \brief Relative residual the iterative solver must reach. Default 1e-10. */
  double tolerance = 1e-10;
  /** \brief Iteration cap of the iterative solver. Default 5000. */
  int max_iterations = 5000;
  /** \brief Default: nullptr. A lock held while the LU factors of a system with at
    * least `exclusive_from` unknowns exist, for callers that solve patches in
    * parallel: the factors are the largest data of a large cloud, and one set at a
    * time keeps the peak down while the other threads build systems and
    * triangulate (the pipeline passes one; see triangulateSphere). */
  std::mutex* factorization_lock = nullptr;
  /** \brief Default: 50000 unknowns; smaller factors are made without the lock. */
  std::size_t exclusive_from = 50000;
};

/** \brief Parameter points of one patch. */
struct Parameterization : StageStatus
{
  /** \brief One parameter point per patch point, in the order of patch_points. */
  Points2 uv;
  /** \brief Relative residual |A x - b| / |b| of the solution, both coordinates. */
  double residual = 0.0;
  /** \brief Iterations of the iterative solver; for the direct one, the steps that
    * refined its solution in double precision. */
  int iterations = 0;
  /** \brief Whether the direct solver factored in double precision: its single
    * precision factors (the default, for memory) failed or did not refine to the
    * tolerance, on a matrix too ill-conditioned for them. */
  bool double_precision_factors = false;
};

/** \brief Solve a system built by buildMeshlessSystem.
  * \return fails (with a message) on a singular matrix, non-convergence, a
  *         residual above tolerance or non-finite parameter points; never returns
  *         a garbage map as success.
  */
Parameterization
solveMeshlessSystem (const MeshlessSystem& system,
                     const std::vector<pcl::index_t>& patch_points,
                     const std::vector<pcl::index_t>& boundary_loop,
                     const Points2& boundary_uv,
                     const SolveOptions& options = {});

} // namespace meshless
} // namespace pcl
