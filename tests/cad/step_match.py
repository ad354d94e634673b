"""Matching a STEP file's faces to the reference samples Taut wrote beside it (check_step.py's
--reference): each reference face is matched when the STEP face nearest its middle sample holds
its samples within the match tolerance."""

from OCP.BRep import BRep_Tool
from OCP.BRepBndLib import BRepBndLib
from OCP.BRepTools import BRepTools
from OCP.Bnd import Bnd_Box

from step_geometry import BoxGrid, distance, max_or_none

# How far the middle sample may be from its STEP face, in match tolerances, for a match.
MATCH_FACTOR = 100.0


def middle_sample_index(samples):
    """Index of the sample nearest the middle of the samples' (u, v) range."""
    us = [s[0] for s in samples]
    vs = [s[1] for s in samples]
    um = 0.5 * (min(us) + max(us))
    vm = 0.5 * (min(vs) + max(vs))
    best, best_d = 0, None
    for i, s in enumerate(samples):
        d = (s[0] - um) ** 2 + (s[1] - vm) ** 2
        if best_d is None or d < best_d:
            best, best_d = i, d
    return best


def scoring_samples(samples, middle):
    """The middle sample and up to four more spread over the list."""
    n = len(samples)
    picks = [middle] + [round(i * (n - 1) / 3) for i in range(4)]
    seen = []
    for i in picks:
        if i not in seen:
            seen.append(i)
    return [samples[i] for i in seen]


def surface_distance(surface, sample):
    p = surface.Value(sample[0], sample[1])
    return distance((p.X(), p.Y(), p.Z()), sample[2:5])


def in_domain(domain, sample):
    """Whether the sample's (u, v) lies in the face's parameter bounds. Outside them a B-spline
    surface extends its end spans, so a neighbouring face cut from the same spans would evaluate
    to the sample too."""
    umin, umax, vmin, vmax = domain
    slack_u = 1e-9 * max(1.0, umax - umin)
    slack_v = 1e-9 * max(1.0, vmax - vmin)
    return (umin - slack_u <= sample[0] <= umax + slack_u
            and vmin - slack_v <= sample[1] <= vmax + slack_v)


def face_box(face, pad):
    box = Bnd_Box()
    BRepBndLib.Add_s(face, box, False)
    lo = box.CornerMin()
    hi = box.CornerMax()
    return ((lo.X() - pad, lo.Y() - pad, lo.Z() - pad), (hi.X() + pad, hi.Y() + pad, hi.Z() + pad))


def match_reference(faces, reference):
    """Matches reference faces to STEP faces and measures the samples' distances."""
    tolerance = reference["match_tolerance"]
    limit = MATCH_FACTOR * tolerance
    surfaces = [BRep_Tool.Surface_s(face) for face in faces]
    domains = [BRepTools.UVBounds_s(face) for face in faces]
    boxes = [face_box(face, limit) for face in faces]

    # A cell about the size of a typical face keeps each face in a few cells.
    sizes = sorted(max(hi[i] - lo[i] for i in range(3)) for lo, hi in boxes)
    cell = max(sizes[len(sizes) // 2] if sizes else 1.0, limit, 1e-9)
    grid = BoxGrid(cell)
    for index, (lo, hi) in enumerate(boxes):
        grid.add(index, lo, hi)

    matches_per_step_face = [0] * len(faces)
    unmatched = []
    max_sample_distance = None
    for ref_index, samples in enumerate(reference["faces"]):
        middle = middle_sample_index(samples)
        scored = scoring_samples(samples, middle)
        best, best_score = None, None
        for candidate in grid.holding(samples[middle][2:5]):
            if not in_domain(domains[candidate], samples[middle]):
                continue
            surface = surfaces[candidate]
            if surface_distance(surface, samples[middle]) > limit:
                continue
            score = sum(surface_distance(surface, s) for s in scored) / len(scored)
            if best_score is None or score < best_score:
                best, best_score = candidate, score
        if best is None:
            unmatched.append(ref_index)
            continue
        matches_per_step_face[best] += 1
        for sample in samples:
            max_sample_distance = max_or_none(
                max_sample_distance, surface_distance(surfaces[best], sample))

    return {
        "reference_faces": len(reference["faces"]),
        "faces_matched": len(reference["faces"]) - len(unmatched),
        "unmatched_reference_faces": len(unmatched),
        "unmatched_reference_face_indices": unmatched[:20],
        "max_sample_distance": max_sample_distance,
        "step_faces_unmatched": sum(1 for m in matches_per_step_face if m == 0),
        "step_faces_matched_twice": sum(1 for m in matches_per_step_face if m > 1),
    }
