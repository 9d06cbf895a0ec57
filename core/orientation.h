// Orientation: where a volume's index axes point in the world, as its file says (DICOM's Image Orientation
// (Patient), a NRRD's space directions, a NIfTI's sform or qform, a MetaImage's TransformMatrix, a .vti's
// Direction), and how a camera or a clip plane given in the world is seen from the volume's own axes. Plain
// data and pure functions; any thread.
//
// The world is the patient's LPS frame for medical formats (+x left, +y posterior, +z superior: DICOM's and
// ITK's), the file's own frame otherwise. The volume is turned about the center of its extent [0, n s]: the
// center stays where it was, and the file's origin is not used, so that a volume whose axes already point
// along the world's is placed exactly as before (docs/RENDERING.md "Spaces").
#pragma once

#include <optional>
#include <string>
#include <utility>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/render_params.h"

namespace ropecast {

// The columns are the unit world directions of the index axes x, y and z. Identity: the axes are the
// world's.
using AxisDirections = glm::dmat3;

// Three axis vectors of any length (a NRRD's space directions, a sform's columns) as unit directions, or
// nullopt where they are not orthogonal to within a thousandth (a sheared grid) or have a zero or non-finite
// length.
std::optional<AxisDirections> axisDirectionsOf(glm::dvec3 x, glm::dvec3 y, glm::dvec3 z);

// RAS (+x right, +y anterior: NIfTI's, and a NRRD's "right-anterior-superior") to LPS.
AxisDirections rasToLps(const AxisDirections& ras);

// Whether the directions mirror (a left-handed frame: determinant -1).
bool mirrors(const AxisDirections& d);

// Whether every axis lies along a world axis (to within a millionth).
bool isAxisAligned(const AxisDirections& d);

// Three letters, the world direction each index axis points to, x first, in the LPS frame (L or R, P or A,
// S or I): "LPS" for the identity, "RAS" for x and y reversed; each letter the axis's largest component.
// Followed by " (oblique)" where an axis is not along a world axis.
std::string orientationCode(const AxisDirections& d);

// The side of the patient a world direction points to, as radiology viewers letter the edges of an image:
// the LPS letter of each component whose size is at least kDirectionLetterShare of the direction's length,
// the largest first (ties: x before y before z). "L" for +x, "RA" for (-1, -0.5, 0), "" for a zero vector.
inline constexpr double kDirectionLetterShare = 0.3;
std::string directionLetters(glm::dvec3 worldDirection);

// A camera given in the world, as seen in the volume's unturned frame (world = center + d (p - center)):
// eye and target moved, up turned. Exact for the identity.
Camera cameraInVolume(const Camera& world, const AxisDirections& d, glm::dvec3 center);

// The same for a clip plane (its point moved, its normal turned).
ClipPlane clipPlaneInVolume(const ClipPlane& world, const AxisDirections& d, glm::dvec3 center);

// The plane --mode slice shows where none is given: the axial plane (normal +z: superior in a patient's
// frame, across a stack's own slices otherwise) through the world center of the box `params` draw (the volume
// box [0, dims spacing] cut to --crop, turned by `d` about the extent's center).
ClipPlane defaultSlicePlane(const RenderParams& params, glm::u32vec3 dims, glm::dvec3 spacing,
                            const AxisDirections& d);

// The plane of --slice AXIS:INDEX: through the centers of the voxels `index` along the volume's axis `axis`
// (0, 1, 2: x, y, z; voxel i spans [i, i + 1) s, its center at (i + 0.5) s) and the center of the box
// `params` draw, its normal that axis, all turned into the world by `d` about the extent's center.
ClipPlane voxelSlicePlane(const RenderParams& params, int axis, uint32_t index, glm::u32vec3 dims,
                          glm::dvec3 spacing, const AxisDirections& d);

// The six views radiology viewers name (3D Slicer's A, P, L, R, S and I): the eye on that side of the
// patient in the world's LPS frame (anterior: toward -y; left: toward +x; superior: toward +z), looking at
// the center of the box [boxMin, boxMax] from `distance` bounding-sphere radii (as orbitCamera's). Superior
// is up, and anterior in the views from above and below. For a volume whose file gives no orientation the
// names stand for those world axes all the same.
enum class AnatomicalView { Anterior, Posterior, Left, Right, Superior, Inferior };
inline constexpr std::pair<const char*, AnatomicalView> kAnatomicalViewNames[] = {
    {"anterior", AnatomicalView::Anterior}, {"posterior", AnatomicalView::Posterior},
    {"left", AnatomicalView::Left},         {"right", AnatomicalView::Right},
    {"superior", AnatomicalView::Superior}, {"inferior", AnatomicalView::Inferior}};
Camera anatomicalViewCamera(AnatomicalView view, double distance, glm::dvec3 boxMin, glm::dvec3 boxMax,
                            double fovYDeg);

}  // namespace ropecast
