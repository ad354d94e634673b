"""Measures a STEP file with OpenCascade, an independent CAD kernel, for Taut's export tests.

Run with the Python of the virtual environment that tests/run-all.sh makes (it holds PyPI's
cadquery-ocp-novtk, OpenCascade's Python binding):

    $TAUT_CAD_PYTHON tests/cad/check_step.py FILE.step [--reference REF.json] [--heal]

It prints ONE JSON object on stdout and exits 0 whenever it could measure, however bad the model:
the Rust tests decide what is acceptable. When it cannot measure (no such file, OpenCascade cannot
read it, nothing in it transfers to a shape, a malformed reference) it prints one line on stderr and
exits 2.

Units: OpenCascade converts what it reads to millimetres (its default, set explicitly below), so
every length, area and volume below is in mm, mm^2 and mm^3 whatever unit the file declares;
`length_unit` tells the unit the file itself declares.

Healing: OpenCascade's STEP reader "heals" shapes by default as it transfers them (it re-orients
faces, reverses inside-out solids, fixes tolerances...), which would hide the very mistakes these
tests look for. This script turns every healing mode off, so the measurements are of the file as
written; `--heal` keeps OpenCascade's default healing, as a CAD user's import would.

What it reports (keys of the JSON object):
  read_status         true when STEPControl_Reader.ReadFile returned IFSelect_RetDone (always true
                      when the JSON is printed: a failed read exits 2)
  roots_transferred   number of roots STEPControl_Reader.TransferRoots transferred
  length_unit         the file's length unit as OpenCascade names it ("millimetre"), or null
  measurement_unit    "mm": the unit of all lengths below
  healing             whether OpenCascade's shape healing ran on the transferred shape
  valid               BRepCheck_Analyzer(shape).IsValid()
  invalid_subshapes   when not valid: how many solids, shells, faces, wires, edges and vertices
                      BRepCheck finds invalid on their own ({} when valid); a face turned the
                      wrong way shows as an invalid solid
  solids, shells, faces, edges, vertices   distinct sub-shapes of each kind
  closed_shells       shells for which BRep_Tool.IsClosed is true
  free_edges          edges used by exactly one face (degenerated edges, at a pole, not counted)
  nonmanifold_edges   edges used by more than two faces
  seam_edges          edges used twice by one face (the seam of a closed surface)
  degenerated_edges   edges collapsed to a point (poles)
  misoriented_edges   edges between two face uses that both run the same way along them: the two
                      faces disagree about which side is outside (0 on a well-oriented shell)
  volume              BRepGProp.VolumeProperties of the whole shape, adaptive (relative 1e-9 asked);
                      signed as OpenCascade gives it: positive for an outward-oriented closed solid
                      (about 2e-7 relative error on a rational B-spline sphere)
  area                BRepGProp.SurfaceProperties of the whole shape, same precision
  face_surface_types  faces counted by BRepAdaptor_Surface type, e.g. {"BSplineSurface": 24}
  normal_angles       number of smooth edges measured: edges between exactly two face uses (two
                      faces, or one face across its seam) not listed as sharp in the reference
  max_normal_angle_deg  the largest angle, in degrees, between the two faces' outward normals over
                      16 points inside each smooth edge (null when no edge was measured). Each point
                      of the edge's 3D curve is projected on each face's surface
                      (GeomAPI_ProjectPointOnSurf within the face's parameter bounds; for a seam the
                      edge's two pcurves give the parameters), the unit normal there comes from
                      GeomLProp_SLProps and is flipped when the face is TopAbs_REVERSED.
  max_normal_angle_edge_midpoint  [x, y, z] of the edge where that largest angle is (or null)
  sharp_normal_angles, max_sharp_edge_angle_deg  the same for the edges listed as sharp (null
                      when none): on a true G0 crease the angle is well above zero
  max_edge_to_surface_distance  the largest distance from a sampled edge point to its projection
                      on a face using it: the gap between an edge and its faces
  normal_samples_skipped  sample points where a projection failed or a normal was undefined

With --reference REF.json (written by the Rust tests from Taut's exact surface):
  {"faces": [{"samples": [[u, v, x, y, z], ...]}, ...],
   "sharp_edge_midpoints": [[x, y, z], ...],
   "match_tolerance": t}
  The B-spline surfaces in the file keep Taut's parameterisation, so the STEP face made from a
  reference face evaluates, at each sample's own (u, v), to that sample's (x, y, z). Each reference
  face is matched to the STEP face whose surface, evaluated at up to five of the reference's
  (u, v) (the sample nearest the middle of its parameter range and four spread over the list), is
  closest on average. Only STEP faces whose parameter bounds hold the middle sample's (u, v) and
  whose bounding box, grown by 100 * t, holds its (x, y, z) are candidates (a grid of boxes, so
  matching is not quadratic in the face count). A reference face with no candidate within 100 * t
  at its middle sample is unmatched. An edge is sharp when the 3D point at the middle of its
  parameter range lies within t of a listed sharp midpoint.
  It adds:
  reference_faces, faces_matched, unmatched_reference_faces (counts), and
  unmatched_reference_face_indices (the first 20, indices into "faces")
  max_sample_distance  the largest |surface.Value(u, v) - (x, y, z)| over every sample of every
                      matched face (null when none matched)
  step_faces_unmatched        STEP faces no reference face matched
  step_faces_matched_twice    STEP faces more than one reference face matched
  sharp_edges                 edges found sharp
  unmatched_sharp_midpoints   listed sharp midpoints with no edge within t
"""

import argparse
import json
import os
import sys

EXIT_CANNOT_MEASURE = 2

try:
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Curve2d, BRepAdaptor_Surface
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.BRepTools import BRepTools
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.GeomLProp import GeomLProp_SLProps
    from OCP.GProp import GProp_GProps
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_Reader
    from OCP.ShapeFix import ShapeFix_Edge
    from OCP.TCollection import TCollection_AsciiString
    from OCP.TopAbs import (TopAbs_EDGE, TopAbs_FACE, TopAbs_FORWARD, TopAbs_REVERSED,
                            TopAbs_SHELL, TopAbs_SOLID, TopAbs_VERTEX, TopAbs_WIRE)
    from OCP.TopExp import TopExp, TopExp_Explorer
    from OCP.TopoDS import TopoDS
    from OCP.gp import gp_Pnt
    # OpenCascade 8's collection templates (OCP's names for NCollection instances).
    from OCP.collections import (
        DataMap_TCollection_AsciiString_TCollection_AsciiString as ParameterMap,
        IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeAncestorsMap,
        IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeMap,
        Sequence_TCollection_AsciiString as AsciiStringSequence,
    )
except ImportError as import_error:
    sys.stderr.write("check_step: cannot import OCP (%s); run it with $TAUT_CAD_PYTHON, the "
                     "environment tests/run-all.sh makes\n" % import_error)
    sys.exit(EXIT_CANNOT_MEASURE)

# Beside this script: plain geometry, and the matching of faces to a reference.
from step_geometry import PointGrid, angle_deg, json_safe, max_or_none  # noqa: E402
from step_match import match_reference  # noqa: E402

# Points sampled inside each edge for the normal angles.
EDGE_SAMPLES = 16
# Relative precision asked of the adaptive volume and area integration. OpenCascade's non-adaptive
# default is off by 4e-4 on a rational B-spline sphere; asking 1e-9 leaves 2e-7 there (the
# integrator's own error estimate is not to be trusted) for about a millisecond a face.
GPROP_EPS = 1e-9
# Every FixShape mode OpenCascade's reader knows; all set to 0 (off) to read the file as written.
FIX_SHAPE_MODES = [
    "FixFreeShellMode", "FixFreeFaceMode", "FixFreeWireMode", "FixSameParameterMode",
    "FixSolidMode", "FixShellOrientationMode", "CreateOpenSolidMode", "FixShellMode",
    "FixFaceOrientationMode", "FixFaceMode", "FixWireMode", "FixOrientationMode",
    "FixAddNaturalBoundMode", "FixMissingSeamMode", "FixSmallAreaWireMode",
    "RemoveSmallAreaFaceMode", "FixIntersectingWiresMode", "FixLoopWiresMode",
    "FixSplitFaceMode", "AutoCorrectPrecisionMode", "ModifyTopologyMode", "ModifyGeometryMode",
    "ClosedWireMode", "PreferencePCurveMode", "FixReorderMode", "FixSmallMode",
    "FixConnectedMode", "FixEdgeCurvesMode", "FixDegeneratedMode", "FixLackingMode",
    "FixSelfIntersectionMode", "RemoveLoopMode", "FixReversed2dMode", "FixRemovePCurveMode",
    "FixRemoveCurve3dMode", "FixAddPCurveMode", "FixAddCurve3dMode", "FixSeamMode",
    "FixShiftedMode", "FixEdgeSameParameterMode", "FixNotchedEdgesMode", "FixTailMode",
    "FixSelfIntersectingEdgeMode", "FixIntersectingEdgesMode",
    "FixNonAdjacentIntersectingEdgesMode", "FixVertexPositionMode", "FixVertexToleranceMode",
]


class CannotMeasure(Exception):
    """Raised with a one-line reason when the file cannot be measured at all."""


def fail(message):
    """Prints one line on stderr and exits non-zero."""
    line = " ".join(str(message).split())
    sys.stderr.write("check_step: " + line + "\n")
    sys.stderr.flush()
    sys.exit(EXIT_CANNOT_MEASURE)


def keep_stdout_for_json():
    """OpenCascade prints progress from C++ straight to file descriptor 1, which would spoil the
    one JSON object. Returns a stream on the real stdout and points descriptor 1 at /dev/null."""
    sys.stdout.flush()
    json_fd = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.close(devnull)
    return os.fdopen(json_fd, "w")


# ---------------------------------------------------------------------------------------------
# Reference file


def load_reference(path):
    """Reads and checks the reference JSON; raises CannotMeasure when it is malformed."""
    try:
        with open(path, "r", encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        raise CannotMeasure("cannot read reference %s: %s" % (path, e))
    if not isinstance(data, dict):
        raise CannotMeasure("reference %s is not a JSON object" % path)
    tolerance = data.get("match_tolerance")
    if not isinstance(tolerance, (int, float)) or not tolerance > 0:
        raise CannotMeasure("reference %s needs a positive match_tolerance" % path)
    faces = data.get("faces", [])
    if not isinstance(faces, list):
        raise CannotMeasure("reference %s: faces is not a list" % path)
    checked_faces = []
    for index, face in enumerate(faces):
        samples = face.get("samples") if isinstance(face, dict) else None
        if not isinstance(samples, list) or not samples:
            raise CannotMeasure("reference %s: face %d has no samples" % (path, index))
        for sample in samples:
            if not (isinstance(sample, list) and len(sample) == 5):
                raise CannotMeasure(
                    "reference %s: face %d has a sample that is not [u, v, x, y, z]" % (path, index))
        checked_faces.append([[float(c) for c in sample] for sample in samples])
    midpoints = data.get("sharp_edge_midpoints", [])
    if not isinstance(midpoints, list) or any(
            not (isinstance(p, list) and len(p) == 3) for p in midpoints):
        raise CannotMeasure("reference %s: sharp_edge_midpoints must be [[x, y, z], ...]" % path)
    return {
        "faces": checked_faces,
        "sharp_edge_midpoints": [[float(c) for c in p] for p in midpoints],
        "match_tolerance": float(tolerance),
    }


# ---------------------------------------------------------------------------------------------
# OpenCascade


def read_step(path, heal):
    """Reads and transfers the file; returns (shape, facts about the read)."""
    if not os.path.isfile(path):
        raise CannotMeasure("no such file: %s" % path)
    reader = STEPControl_Reader()  # also registers the STEP parameters set next
    # OpenCascade's default output unit, set so that a changed default cannot change the numbers.
    Interface_Static.SetCVal_s("xstep.cascade.unit", "MM")
    status = reader.ReadFile(path)
    if status != IFSelect_RetDone:
        raise CannotMeasure("OpenCascade cannot read %s: %s" % (path, status.name))
    if not heal:
        # Must follow ReadFile: before it, the reader replaces these parameters with its defaults.
        parameters = ParameterMap()
        for mode in FIX_SHAPE_MODES:
            parameters.Bind(TCollection_AsciiString("FixShape." + mode), TCollection_AsciiString("0"))
        reader.SetShapeFixParameters(parameters)
    roots = reader.TransferRoots()
    shape = reader.OneShape()
    if roots == 0 or shape.IsNull():
        raise CannotMeasure("nothing in %s transferred to a shape" % path)
    if not heal:
        add_missing_pcurves(shape)
    return shape, {
        "read_status": True,
        "roots_transferred": int(roots),
        "length_unit": file_length_unit(reader),
        "measurement_unit": "mm",
        "healing": bool(heal),
    }


def add_missing_pcurves(shape):
    """Gives every edge its curve in each face's parameter plane where the file has none.

    STEP does not require these (an AP214 edge has only its 3D curve) and every importer makes
    them; with healing off OpenCascade does not, and its validity check then fails every wire.
    Projecting the 3D curve onto the face changes no orientation and no geometry.
    """
    fixer = ShapeFix_Edge()
    faces = TopExp_Explorer(shape, TopAbs_FACE)
    while faces.More():
        face = TopoDS.Face(faces.Current())
        edges = TopExp_Explorer(face, TopAbs_EDGE)
        while edges.More():
            edge = TopoDS.Edge(edges.Current())
            fixer.FixAddPCurve(edge, face, False)
            fixer.FixSameParameter(edge)
            edges.Next()
        faces.Next()


def file_length_unit(reader):
    names = AsciiStringSequence()
    angles = AsciiStringSequence()
    solid_angles = AsciiStringSequence()
    try:
        reader.FileUnits(names, angles, solid_angles)
    except Exception:  # the unit is a convenience; the measurements are in mm regardless
        return None
    units = sorted({names.Value(i).ToCString() for i in range(1, names.Length() + 1)})
    if not units:
        return None
    return units[0] if len(units) == 1 else ",".join(units)


def unique_subshapes(shape, kind):
    """The distinct sub-shapes of one kind, in a stable order (faces as TopoDS_Face)."""
    indexed = ShapeMap()
    TopExp.MapShapes_s(shape, kind, indexed)
    found = [indexed.FindKey(i) for i in range(1, indexed.Extent() + 1)]
    if kind == TopAbs_FACE:
        found = [TopoDS.Face(f) for f in found]
    return found


def edge_face_uses(shape):
    """[(edge, [face, ...])] with one face per use of the edge: a seam lists its face twice."""
    ancestors = ShapeAncestorsMap()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, ancestors)
    result = []
    for i in range(1, ancestors.Extent() + 1):
        edge = TopoDS.Edge(ancestors.FindKey(i))
        faces = [TopoDS.Face(f) for f in ancestors.FindFromIndex(i)]
        result.append((edge, faces))
    return result


def misoriented_edge_count(shape):
    """Edges used twice, both times in the same direction. Walking the faces with their
    orientation composed from the shell and solid, a consistently oriented shell runs each
    shared edge once forward and once reversed."""
    edges = ShapeMap()
    TopExp.MapShapes_s(shape, TopAbs_EDGE, edges)
    directions = {}  # edge index -> orientations of its uses
    faces = TopExp_Explorer(shape, TopAbs_FACE)
    while faces.More():
        face_edges = TopExp_Explorer(faces.Current(), TopAbs_EDGE)
        while face_edges.More():
            edge = face_edges.Current()
            directions.setdefault(edges.FindIndex(edge), []).append(edge.Orientation())
            face_edges.Next()
        faces.Next()
    count = 0
    for index, uses in directions.items():
        if len(uses) != 2 or BRep_Tool.Degenerated_s(TopoDS.Edge(edges.FindKey(index))):
            continue
        if uses[0] == uses[1] and uses[0] in (TopAbs_FORWARD, TopAbs_REVERSED):
            count += 1
    return count


def validity(shape):
    analyzer = BRepCheck_Analyzer(shape)
    valid = bool(analyzer.IsValid())
    invalid = {}
    if not valid:
        kinds = [("solids", TopAbs_SOLID), ("shells", TopAbs_SHELL),
                 ("faces", TopAbs_FACE), ("wires", TopAbs_WIRE),
                 ("edges", TopAbs_EDGE), ("vertices", TopAbs_VERTEX)]
        for name, kind in kinds:
            bad = sum(1 for sub in unique_subshapes(shape, kind) if not analyzer.IsValid(sub))
            if bad:
                invalid[name] = bad
    return {"valid": valid, "invalid_subshapes": invalid}


def topology_counts(shape, uses):
    shells = unique_subshapes(shape, TopAbs_SHELL)
    counts = {
        "solids": len(unique_subshapes(shape, TopAbs_SOLID)),
        "shells": len(shells),
        "closed_shells": sum(1 for shell in shells if BRep_Tool.IsClosed_s(shell)),
        "faces": len(unique_subshapes(shape, TopAbs_FACE)),
        "edges": len(unique_subshapes(shape, TopAbs_EDGE)),
        "vertices": len(unique_subshapes(shape, TopAbs_VERTEX)),
        "free_edges": 0,
        "nonmanifold_edges": 0,
        "seam_edges": 0,
        "degenerated_edges": 0,
    }
    for edge, faces in uses:
        if BRep_Tool.Degenerated_s(edge):
            counts["degenerated_edges"] += 1
        elif len(faces) == 1:
            counts["free_edges"] += 1
        elif len(faces) > 2:
            counts["nonmanifold_edges"] += 1
        elif faces[0].IsSame(faces[1]):
            counts["seam_edges"] += 1
    counts["misoriented_edges"] = misoriented_edge_count(shape)
    return counts


def mass_properties(shape):
    volume = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, volume, GPROP_EPS)
    area = GProp_GProps()
    BRepGProp.SurfaceProperties_s(shape, area, GPROP_EPS)
    return {"volume": float(volume.Mass()), "area": float(area.Mass())}


def surface_type_counts(faces):
    counts = {}
    for face in faces:
        name = BRepAdaptor_Surface(face).GetType().name
        if name.startswith("GeomAbs_"):
            name = name[len("GeomAbs_"):]
        counts[name] = counts.get(name, 0) + 1
    return counts


def edge_midpoint(edge):
    curve = BRepAdaptor_Curve(edge)
    p = curve.Value(0.5 * (curve.FirstParameter() + curve.LastParameter()))
    return (p.X(), p.Y(), p.Z())


class FaceGeometry:
    """A face's surface with a point projector built once and reused for all its edges' samples."""

    def __init__(self, face):
        self.face = face
        self.surface = BRep_Tool.Surface_s(face)  # with the face's location applied
        self._projector = None

    def project(self, point):
        """(u, v, distance) of the nearest point of the surface within the face's parameter
        bounds, or None when the projection finds nothing."""
        if self._projector is None:
            umin, umax, vmin, vmax = BRepTools.UVBounds_s(self.face)
            self._projector = GeomAPI_ProjectPointOnSurf()
            self._projector.Init(self.surface, umin, umax, vmin, vmax)
        self._projector.Perform(gp_Pnt(*point))
        if not self._projector.IsDone() or self._projector.NbPoints() == 0:
            return None
        u, v = self._projector.LowerDistanceParameters()
        return u, v, self._projector.LowerDistance()

    def normal(self, u, v, face_use):
        """Outward unit normal at (u, v) for the face as used (flipped when the use is
        TopAbs_REVERSED), or None where the surface has no normal (a pole)."""
        props = GeomLProp_SLProps(self.surface, u, v, 1, 1e-9)
        if not props.IsNormalDefined():
            return None
        n = props.Normal()
        sign = -1.0 if face_use.Orientation() == TopAbs_REVERSED else 1.0
        return (sign * n.X(), sign * n.Y(), sign * n.Z())


class FaceGeometries:
    """One FaceGeometry per distinct face, found through OpenCascade's own shape map (a face
    reached with either orientation, or twice along a seam, is the same entry)."""

    def __init__(self, shape):
        self.map = ShapeMap()
        TopExp.MapShapes_s(shape, TopAbs_FACE, self.map)
        self.built = {}

    def of(self, face):
        index = self.map.FindIndex(face)
        geometry = self.built.get(index)
        if geometry is None:
            geometry = FaceGeometry(face)
            self.built[index] = geometry
        return geometry


def edge_normal_angle(edge, face_uses, geometries, stats):
    """Largest angle, in degrees, between the normals of the edge's two face uses over
    EDGE_SAMPLES points inside the edge; None when no sample gave two normals."""
    first_use, second_use = face_uses
    first, second = geometries.of(first_use), geometries.of(second_use)
    curve = BRepAdaptor_Curve(edge)
    t0, t1 = curve.FirstParameter(), curve.LastParameter()
    seam = first_use.IsSame(second_use)
    if seam:
        # One face on both sides: projecting would land on one side only, so the edge's two
        # pcurves give the parameters on either side of the seam.
        forward = BRepAdaptor_Curve2d(TopoDS.Edge(edge.Oriented(TopAbs_FORWARD)), first.face)
        backward = BRepAdaptor_Curve2d(TopoDS.Edge(edge.Oriented(TopAbs_REVERSED)), first.face)
    largest = None
    for k in range(1, EDGE_SAMPLES + 1):
        t = t0 + (t1 - t0) * k / (EDGE_SAMPLES + 1)
        if seam:
            uv1, uv2 = forward.Value(t), backward.Value(t)
            n1 = first.normal(uv1.X(), uv1.Y(), first_use)
            n2 = second.normal(uv2.X(), uv2.Y(), second_use)
        else:
            p = curve.Value(t)
            point = (p.X(), p.Y(), p.Z())
            hit1 = first.project(point)
            hit2 = second.project(point)
            if hit1 is None or hit2 is None:
                stats["normal_samples_skipped"] += 1
                continue
            stats["max_edge_to_surface_distance"] = max(
                stats["max_edge_to_surface_distance"], hit1[2], hit2[2])
            n1 = first.normal(hit1[0], hit1[1], first_use)
            n2 = second.normal(hit2[0], hit2[1], second_use)
        if n1 is None or n2 is None:
            stats["normal_samples_skipped"] += 1
            continue
        largest = max_or_none(largest, angle_deg(n1, n2))
    return largest


def normal_angles(shape, uses, sharp_grid, tolerance):
    """Measures every edge between exactly two face uses, the sharp ones apart from the smooth
    ones. Returns (stats, indices of the sharp midpoints that found an edge)."""
    geometries = FaceGeometries(shape)
    stats = {
        "normal_angles": 0,
        "max_normal_angle_deg": None,
        "max_normal_angle_edge_midpoint": None,
        "sharp_normal_angles": 0,
        "max_sharp_edge_angle_deg": None,
        "max_edge_to_surface_distance": 0.0,
        "normal_samples_skipped": 0,
        "sharp_edges": 0,
    }
    matched_sharp = set()
    for edge, faces in uses:
        if len(faces) != 2 or BRep_Tool.Degenerated_s(edge):
            continue
        midpoint = edge_midpoint(edge)
        sharp_hits = sharp_grid.within(midpoint, tolerance) if sharp_grid else []
        angle = edge_normal_angle(edge, faces, geometries, stats)
        if sharp_hits:
            matched_sharp.update(sharp_hits)
            stats["sharp_edges"] += 1
            if angle is not None:
                stats["sharp_normal_angles"] += 1
                stats["max_sharp_edge_angle_deg"] = max_or_none(
                    stats["max_sharp_edge_angle_deg"], angle)
        elif angle is not None:
            stats["normal_angles"] += 1
            if stats["max_normal_angle_deg"] is None or angle > stats["max_normal_angle_deg"]:
                stats["max_normal_angle_deg"] = angle
                stats["max_normal_angle_edge_midpoint"] = list(midpoint)
    return stats, matched_sharp


def measure(path, reference, heal):
    shape, result = read_step(path, heal)
    faces = unique_subshapes(shape, TopAbs_FACE)
    uses = edge_face_uses(shape)
    result.update(validity(shape))
    result.update(topology_counts(shape, uses))
    result.update(mass_properties(shape))
    result["face_surface_types"] = surface_type_counts(faces)

    sharp_grid = None
    tolerance = 0.0
    if reference is not None:
        tolerance = reference["match_tolerance"]
        sharp_grid = PointGrid(tolerance)
        for index, p in enumerate(reference["sharp_edge_midpoints"]):
            sharp_grid.add(index, p)
    angles, matched_sharp = normal_angles(shape, uses, sharp_grid, tolerance)
    result.update(angles)

    if reference is not None:
        result.update(match_reference(faces, reference))
        result["unmatched_sharp_midpoints"] = (
            len(reference["sharp_edge_midpoints"]) - len(matched_sharp))
    return result


def parse_arguments():
    parser = argparse.ArgumentParser(
        description="Measure a STEP file with OpenCascade; prints one JSON object.")
    parser.add_argument("step", help="the STEP file")
    parser.add_argument("--reference", help="JSON of Taut's exact surface samples and sharp edges")
    parser.add_argument("--heal", action="store_true",
                        help="let OpenCascade heal the shape on transfer, as its default import does")
    return parser.parse_args()


def main():
    args = parse_arguments()
    json_out = keep_stdout_for_json()
    try:
        reference = load_reference(args.reference) if args.reference else None
        result = measure(args.step, reference, args.heal)
    except CannotMeasure as e:
        fail(e)
    except Exception as e:  # an OpenCascade failure on a broken file: still one clean line
        fail("cannot measure %s: %s: %s" % (args.step, type(e).__name__, e))
    json_out.write(json.dumps(json_safe(result), sort_keys=True, allow_nan=False) + "\n")
    json_out.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
