/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include "common/stage_clock.h"

#include <pcl/surface/meshless/reconstruct.h>

#include <optional>
#include <string>
#include <vector>

namespace pcl {
namespace meshless {

using Normals = std::vector<Eigen::Vector3f>;

/** \brief The rings' largest elevation (OrderingOptions) of the runs that try the
  * near side only: around a part a few point spacings across, steeper neighbours
  * lie on its far side. */
constexpr double max_neighbour_elevation_on_retry = 50.0;

/** \brief The width of the Gaussian weights on those runs' plane fits
  * (OrderingOptions::plane_weight_width): the steep neighbours are judged against a
  * plane that the near side carries, not one that stands across the part. */
constexpr double plane_weight_width_on_retry = 0.8;

/** \brief The normal fits a run on the near side's rings tries, in order: the
  * weighted plane, then a sphere through the point, which keeps the tangent plane
  * of a part only four or five points around where a plane takes the part's slice
  * (a sphere may fold where a plane did not, so it comes second). */
constexpr NormalFit near_side_fits[] = {NormalFit::Plane, NormalFit::SphereThroughPoint};
// RetryPolicy::tryNearSide tries the fits after a near side's own: the sphere last.
static_assert (near_side_fits[1] == NormalFit::SphereThroughPoint);

/** \brief `options` for a run on rings of the near side only, fitted by `fit`. */
SpherePipelineOptions
nearSideOptions (SpherePipelineOptions options, NormalFit fit);

/** \brief What finishing did to one triangulation; the report takes it over when
  * that triangulation becomes the result. */
struct FinishedMesh
{
  EdgeSwapResult optimization;
  FoldRepairResult raw_repair, repair;
  MeshReport mesh;
  /** \brief Disc topology: holes whose rims the boundary walk missed, cut open. */
  std::size_t holes_opened = 0;
  /** \brief Disc topology: the share of the area facing against the oriented
    * normals before the final repair (MeshFinisher::areaAgainstNormals). */
  double area_against_normals = 0.0;
};

/** \brief The result so far of one reconstruction: its triangles, the oriented
  * point normals they came with and the report. */
struct CurrentResult
{
  Triangles triangles;
  Normals normals;
  ReconstructionReport report;

  void
  adopt (FinishedMesh&& finished);

  /** \brief Disc topology: the holes the boundary walk found (report.holes counts
    * those cut open by the finished mesh too). */
  std::size_t
  walkHoles () const
  {
    return report.holes - report.holes_opened;
  }
};

/** \brief Whether a fold repair tries longer runs of swaps where few pairs are left
  * (FoldRepairOptions::max_swaps_in_a_row_when_few). */
enum class LongerSwapRuns
{
  Off,
  On
};

/** \brief Turns a raw triangulation into a checked result: the raw folds re-meshed,
  * the edge swaps, the class's own check, the folds left re-meshed, outward
  * orientation, and the invariants of the topology. */
class MeshFinisher
{
public:
  MeshFinisher (const Points3& points, const ReconstructionOptions& options,
                const CurrentResult& current, StageClock& clock);

  /** \brief Neighbourhoods the fold repair uses (the denser ones after k + 2). */
  void
  useNeighbours (const CsrGraph* neighbours)
  {
    neighbours_ = neighbours;
  }

  /** \return an empty string, or what is wrong with the finished mesh. */
  std::string
  finish (Triangles& triangles, const Normals& normals, FinishedMesh& finished);

  /** \brief The share of the mesh's area facing against the oriented normals, the
    * mesh turned as a whole counting as facing along them; 0 without normals. */
  double
  areaAgainstNormals (const Triangles& triangles, const Normals& normals) const;

  /** \brief A closed genus-0 surface through a cloud with handles or a boundary
    * turns back over itself: it intersects itself, and large parts of it face
    * against the normals or it passes through itself between parts far apart. */
  bool
  turnsBack (const Triangles& triangles, const Normals& normals, const MeshReport& mesh,
             double& against, std::size_t& distant) const;

  /** \brief turnsBack on a triangulation as it comes from the pipeline, before the
    * repair re-meshes its folds: a run on other rings may give a genus-0 mesh through
    * a cloud with handles whose crossings the repair then hides. */
  bool
  turnsBackUnrepaired (const Triangles& triangles, const Normals& normals) const;

  /** \brief The last repair of a result that keeps a few pairs after every attempt:
    * runs of swaps longer than each attempt's repair affords
    * (FoldRepairOptions::max_swaps_in_a_row_when_few), then the check again; its
    * runs and the pairs left go into report.fold_repair. Returns false if the
    * progress callback said cancel. */
  bool
  repairWithLongerRuns (Triangles& triangles, const Normals& normals, ReconstructionReport& report);

private:
  /** `longer_runs`: FoldRepairOptions::max_swaps_in_a_row_when_few applies. */
  bool
  repairFolds (Triangles& triangles, const Normals& normals, const MeshReport& mesh,
               const char* stage, LongerSwapRuns longer_runs, FoldRepairResult& repair,
               std::vector<char>* rewritten = nullptr);
  bool
  checkAndRepairRaw (Triangles& triangles, const Normals& normals, FinishedMesh& finished,
                     EdgeSwapOptions& swaps);
  std::string
  optimize (Triangles& triangles, const Normals& normals, FinishedMesh& finished);
  void
  checkFinal (const Triangles& triangles, FinishedMesh& finished);
  std::string
  openMissedHoles (Triangles& triangles, FinishedMesh& finished) const;
  std::string
  verdict (Triangles& triangles, MeshReport& mesh, std::size_t holes_opened) const;

  const Points3& points_;
  const ReconstructionOptions& options_;
  const CurrentResult& current_;
  StageClock& clock_;
  const CsrGraph* neighbours_ = nullptr;
  bool closed_;
  MeshCheckOptions check_;
  // Slots the repair and the swaps rewrite after a raw check that listed all its
  // pairs: the final check then tests only pairs with a triangle rewritten since.
  std::vector<char> rewritten_;
  std::vector<std::pair<std::size_t, std::size_t>> raw_pairs_;
};

/** \brief The sphere pipeline's retries while the result intersects itself, or (sphere
  * topology) keeps neighbours on one side of the surface far apart on the mesh, as a
  * mesh across a part thinner than the spacing does: thin parts separated, further
  * base meshes, the whole sequence on k + 2 neighbours, and for a small cloud in
  * convex position its hull. A run replaces the result only if it is valid, does
  * not turn back and intersects itself less, or no longer keeps neighbours apart. */
class RetryPolicy
{
public:
  /** \param[in] neighbours those of the first run (the given k) */
  RetryPolicy (const Points3& points, const CsrGraph& neighbours,
               const ReconstructionOptions& options, MeshFinisher& finisher,
               CurrentResult& current, StageClock& clock);

  /** \brief All retries after a first run with `first_options`, which they vary.
    * \return false if the progress callback cancelled. */
  bool
  run (const SpherePipelineOptions& first_options, const NeighbourSearch& search);

  /** \brief The neighbours the result keeps apart, if the retries counted them. */
  std::optional<std::size_t>
  separatedNeighbours () const
  {
    return separated_;
  }

  /** \brief Whether a run replaced a result that kept neighbours apart. */
  bool
  replacedOneKeepingNeighboursApart () const
  {
    return replaced_apart_;
  }

  /** \brief Whether the current result turns back (records the figures in the
    * report). */
  bool
  currentTurnsBack ();
  /** \brief Once per call: runs on rings of the near side only (nearSideOptions),
    * one per fit of near_side_fits while pairs (or neighbours kept apart) are left
    * (after `options`' own fit if they are the near side's already), each kept if it
    * does not turn back before its repair and is better (see tryAnother). */
  void
  tryNearSide (const SpherePipelineOptions& options);

  /** \brief Whether tryAnother also asks the triangulation not to turn back before
    * its repair. */
  enum class RawCheck
  {
    None,
    MustNotTurnBack
  };

  /** \brief One more run of the pipeline with `options`; replaces the result if it
    * is better (and, if asked, its triangulation did not turn back before the
    * repair). \return the attempt whose base mesh the run used, or -1. */
  int
  tryAnother (const SpherePipelineOptions& options, bool& kept,
              SpherePipelineStats* stats = nullptr, RawCheck raw_check = RawCheck::None);

  /** \brief The thin-part run, then further base meshes, after a run with
    * `options` whose statistics are `first`. */
  void
  retrySequence (SpherePipelineOptions options, const SpherePipelineStats& first);

private:
  /** \brief Whether the result still has what the retries look to remove. */
  bool
  defective () const;
  /** \brief The neighbours (of the first run) that a mesh keeps apart
    * (neighboursSeparatedByTheMesh), counted in the sphere topology with the
    * intersection check on. */
  std::optional<std::size_t>
  countSeparatedNeighbours (const Triangles& triangles, const Normals& normals);
  bool
  retryDenser (const SpherePipelineOptions& first_options, const NeighbourSearch& search);
  void
  convexHullFallback ();

  const Points3& points_;
  const ReconstructionOptions& options_;
  MeshFinisher& finisher_;
  CurrentResult& current_;
  StageClock& clock_;
  const CsrGraph* neighbours_ = nullptr;
  const CsrGraph& first_neighbours_;
  std::optional<std::size_t> separated_; // the result's, where counted
  bool apart_ = false; // the result has no pairs but keeps neighbours apart
  bool replaced_apart_ = false;
  bool denser_ = false;
  bool near_side_tried_ = false;
  int denser_k_ = 0;
  Neighbourhoods denser_neighbourhoods_;
};

} // namespace meshless
} // namespace pcl
