"""The synthetic quadrupeds of quadrupeds.py keep the promises a morph
benchmark relies on: one closed, outward, genus-0 surface without
degenerate faces or self-intersections, in every kind, size and documented
pose; landmarks at the anatomical extremes and on the same points whatever
the tessellation; poses that keep the connectivity; seeds and face budgets
that change the triangles but not the shape; valid jittered (scan-like)
copies. The self-intersection check itself is checked on meshes that do
intersect (a checker that checks nothing is a classic bug).
"""
import itertools

import numpy as np
import pytest

import meshes
import paramorph_native as pm
import quadrupeds as q

KINDS = ["horse", "cow"]
POSES = {"rest": None, "walk": q.WALK, "gallop": q.GALLOP}


def face_areas(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)


def mean_edge(V, F):
    return float(np.linalg.norm(V[F[:, [1, 2, 0]]] - V[F], axis=2).mean())


def assert_valid_surface(V, F, faces=None):
    assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == 3
    assert F.dtype == np.int32 and F.ndim == 2 and F.shape[1] == 3
    assert np.isfinite(V).all()
    report = pm.validate(V, F, relative_area_tolerance=1e-8)
    assert report.is_closed_genus0, report
    assert (report.components, report.boundary_edges, report.genus) == (1, 0, 0)
    for name in ("non_manifold_edges", "non_manifold_vertices", "degenerate_faces",
                 "isolated_vertices", "inconsistent_orientation_edges"):
        assert getattr(report, name).size == 0, name
    assert meshes.signed_volume(V, F) > 0, "faces must face outwards"
    diag = np.linalg.norm(V.max(0) - V.min(0))
    assert face_areas(V, F).min() > 1e-8 * diag ** 2
    stats = q.mesh_stats(V, F)
    assert stats["min_angle"] > 1.0, stats
    if faces is not None:
        assert abs(len(F) - faces) <= 0.3 * faces, (len(F), faces)


# --- topology, orientation, budgets -------------------------------------------------------

@pytest.mark.parametrize("pose", sorted(POSES))
@pytest.mark.parametrize("faces", [3000, 20000])
@pytest.mark.parametrize("kind", KINDS)
def test_closed_genus0_outward_well_shaped(kind, faces, pose):
    V, F, landmarks = q.quadruped(kind, faces, POSES[pose])
    assert_valid_surface(V, F, faces)
    assert tuple(sorted(landmarks)) == tuple(sorted(q.LANDMARKS))
    ids = np.array([landmarks[name] for name in q.LANDMARKS])
    assert len(set(ids.tolist())) == len(ids), "landmarks are distinct vertices"
    assert ((0 <= ids) & (ids < len(V))).all()
    assert np.isin(ids, F).all(), "landmarks are used vertices"


@pytest.mark.parametrize("kind", KINDS)
def test_large_budget(kind):
    # ~97k faces: generation takes about a second (no timed assertion here;
    # tests/bench times things).
    for pose in (None, q.GALLOP):
        V, F, landmarks = q.quadruped(kind, 97000, pose)
        assert_valid_surface(V, F, 97000)
    assert len(q.self_intersections(V, F)) == 0


@pytest.mark.parametrize("kind", KINDS)
def test_face_budget_tracks_the_request(kind):
    counts = [len(q.quadruped(kind, n)[1]) for n in (3000, 6000, 12000)]
    for n, m in zip((3000, 6000, 12000), counts):
        assert abs(m - n) <= 0.3 * n
    assert counts[0] < counts[1] < counts[2]


# --- landmarks ------------------------------------------------------------------------------

@pytest.mark.parametrize("faces", [3000, 20000])
@pytest.mark.parametrize("kind", KINDS)
def test_landmarks_at_the_extremes_in_rest_pose(kind, faces):
    V, F, L, parts = q.quadruped(kind, faces, return_parts=True)
    for leg in q.LEGS:
        hoof = L["hoof_" + leg[4:]]
        assert hoof in parts[leg]
        assert V[hoof, 2] <= V[parts[leg], 2].min() + 1e-12, f"{leg}: hoof is its lowest vertex"
        assert V[hoof, 2] <= V[:, 2].min() + 1e-9, "every hoof stands on the ground"
        assert np.sign(V[hoof, 0]) == (1 if leg[4] == "f" else -1), "front legs in front"
        assert np.sign(V[hoof, 1]) == (1 if leg[5] == "l" else -1), "left legs at +y"
    muzzle = L["muzzle"]
    assert muzzle in parts["neck"]
    assert V[muzzle, 0] >= V[:, 0].max() - 1e-12, "muzzle is the most forward vertex"
    tail = L["tail"]
    assert tail in parts["tail"]
    assert V[tail, 0] < V[parts["torso"], 0].min() - 0.2, "tail tip behind the body"
    assert V[tail, 0] < V[:, 0].min() + 0.1, "tail tip in the rearmost region"
    assert V[tail, 2] < V[parts["torso"], 2].min(), "tail hangs below the belly"


@pytest.mark.parametrize("kind", KINDS)
def test_landmarks_are_the_same_points_for_any_tessellation(kind):
    ref = None
    for faces, seed, jitter in [(3000, 0, 0.0), (6000, 1, 0.0), (20000, 2, 0.0), (6000, 3, 0.3)]:
        for name, pose in POSES.items():
            V, F, L = q.quadruped(kind, faces, pose, seed=seed, jitter=jitter)
            P = np.array([V[L[k]] for k in q.LANDMARKS])
            if ref is None:
                ref = {}
            if name not in ref:
                ref[name] = P
            assert np.abs(P - ref[name]).max() <= 1e-9, (faces, seed, jitter, name)
    assert np.abs(ref["gallop"] - ref["rest"]).max() > 0.3, "the pose moves the landmarks"


def test_kinds_have_the_same_landmarks_on_different_shapes():
    (Vh, Fh, Lh, Ph), (Vc, Fc, Lc, Pc) = (q.quadruped(k, 6000, return_parts=True) for k in KINDS)
    assert set(Lh) == set(Lc) == set(q.LANDMARKS)
    assert "horn_l" in Pc and "horn_r" in Pc and "horn_l" not in Ph

    def legs_over_length(V, L, P):
        torso = V[P["torso"]]
        length = np.ptp(torso[:, 0])
        withers = torso[:, 2].max()
        return (withers - V[L["hoof_fl"], 2]) / length

    horse, cow = legs_over_length(Vh, Lh, Ph), legs_over_length(Vc, Lc, Pc)
    assert 0.85 < horse < 1.1, "horse: ground to withers about the torso's length"
    assert 0.65 < cow < 0.85, "cow: clearly shorter legs"
    depth = [np.ptp(V[P["torso"], 2]) / np.ptp(V[P["torso"], 1]) for V, P in ((Vh, Ph), (Vc, Pc))]
    assert depth[0] > 1.0 and depth[1] > 1.0
    assert meshes.signed_volume(Vc, Fc) > 1.3 * meshes.signed_volume(Vh, Fh), "cow is heavier"


# --- poses, seeds, budgets -------------------------------------------------------------------

@pytest.mark.parametrize("kind", KINDS)
def test_pose_keeps_connectivity_and_landmark_ids(kind):
    V0, F0, L0 = q.quadruped(kind, 6000, seed=5)
    for pose in (q.WALK, q.GALLOP, {"neck": 25.0}, {"leg_hr": (-40.0, 60.0), "tail": 60.0}):
        V, F, L = q.quadruped(kind, 6000, pose, seed=5)
        assert np.array_equal(F, F0)
        assert L == L0
        assert V.shape == V0.shape and not np.allclose(V, V0)
    # the rest pose is the empty pose
    V, F, L = q.quadruped(kind, 6000, {}, seed=5)
    assert np.allclose(V, V0, atol=1e-12)


@pytest.mark.parametrize("kind", KINDS)
def test_pose_moves_only_what_it_names(kind):
    V0, F0, L0, P = q.quadruped(kind, 6000, return_parts=True)
    V, F, L = q.quadruped(kind, 6000, {"leg_fl": (30.0, 40.0)})
    moved = np.linalg.norm(V - V0, axis=1) > 1e-12
    assert moved[P["leg_fl"]].mean() > 0.7
    others = np.concatenate([P[k] for k in P if k != "leg_fl"])
    assert not moved[others].any()
    # forward swing with a flexed knee: the hoof comes forward and up
    assert V[L["hoof_fl"], 0] > V0[L["hoof_fl"], 0] and V[L["hoof_fl"], 2] > V0[L["hoof_fl"], 2]
    Vn, _, Ln = q.quadruped(kind, 6000, {"neck": 25.0})
    assert Vn[Ln["muzzle"], 2] > V0[L0["muzzle"], 2], "neck > 0 raises the head"
    Vt, _, Lt = q.quadruped(kind, 6000, {"tail": 50.0})
    assert Vt[Lt["tail"], 2] > V0[L0["tail"], 2], "tail > 0 lifts the tail"


def nearest_distances(A, B, chunk=1500):
    out = np.empty(len(A))
    for c in range(0, len(A), chunk):
        out[c:c + chunk] = np.sqrt(((A[c:c + chunk, None] - B[None]) ** 2).sum(-1)).min(1)
    return out


@pytest.mark.parametrize("kind", KINDS)
def test_seed_changes_triangles_not_shape(kind):
    V1, F1, L1 = q.quadruped(kind, 6000, q.GALLOP, seed=1)
    V2, F2, L2 = q.quadruped(kind, 6000, q.GALLOP, seed=2)
    assert F1.shape != F2.shape or not np.array_equal(F1, F2), "another connectivity"
    assert not (V1.shape == V2.shape and np.allclose(V1, V2)), "other vertices"
    vol1, vol2 = meshes.signed_volume(V1, F1), meshes.signed_volume(V2, F2)
    assert abs(vol1 - vol2) < 0.01 * vol1
    area1, area2 = face_areas(V1, F1).sum(), face_areas(V2, F2).sum()
    assert abs(area1 - area2) < 0.01 * area1
    # every vertex of one lies near the other's surface (vertices within an edge)
    h = max(mean_edge(V1, F1), mean_edge(V2, F2))
    assert nearest_distances(V1[::3], V2).max() < 1.5 * h
    assert nearest_distances(V2[::3], V1).max() < 1.5 * h
    # same seed: identical
    V3, F3, L3 = q.quadruped(kind, 6000, q.GALLOP, seed=1)
    assert np.array_equal(F1, F3) and np.array_equal(V1, V3) and L1 == L3


@pytest.mark.parametrize("kind", KINDS)
def test_faces_change_triangles_not_shape(kind):
    Va, Fa, La = q.quadruped(kind, 6000)
    Vb, Fb, Lb = q.quadruped(kind, 20000)
    assert len(Fb) > 2.5 * len(Fa)
    vola, volb = meshes.signed_volume(Va, Fa), meshes.signed_volume(Vb, Fb)
    assert abs(vola - volb) < 0.03 * volb, "only the chords' error differs"
    assert nearest_distances(Vb[::5], Va).max() < 1.5 * mean_edge(Va, Fa)


# --- self-intersections ---------------------------------------------------------------------

def test_self_intersection_check_finds_crossings():
    V, F = meshes.icosphere(3)
    V2, F2 = transform(V, F, offset=(1.5, 0.2, 0.1))
    both_V, both_F = np.vstack([V, V2]), np.vstack([F, F2 + len(V)]).astype(np.int32)
    assert len(q.self_intersections(both_V, both_F)) > 0
    apart_V = np.vstack([V, V + [2.5, 0, 0]])
    assert len(q.self_intersections(apart_V, both_F)) == 0
    assert len(q.self_intersections(*meshes.tentacle_sphere(3))) == 0
    # and on the animal: a front leg swung back and a hind leg swung forward,
    # both flexed (outside the documented poses), cross under the horse
    pose = {"leg_fl": (-40.0, 30.0), "leg_hl": (40.0, 60.0)}
    assert not q.pose_in_range(pose)
    V, F, L = q.quadruped("horse", 6000, pose)
    assert len(q.self_intersections(V, F)) > 0


def transform(V, F, **kw):
    return q.transform(V, F, **kw)


@pytest.mark.parametrize("pose", sorted(POSES))
@pytest.mark.parametrize("kind", KINDS)
def test_no_self_intersections(kind, pose):
    for faces in (3000, 20000):
        V, F, L, parts = q.quadruped(kind, faces, POSES[pose], return_parts=True)
        assert len(q.self_intersections(V, F)) == 0, faces
        gaps = q.part_distances(V, parts)
        worst = min(gaps, key=gaps.get)
        assert gaps[worst] > 0.05, (worst, gaps[worst])


@pytest.mark.parametrize("kind", KINDS)
def test_documented_pose_ranges_are_free_of_intersections(kind):
    V0, F, L, parts = q.quadruped(kind, 3000, return_parts=True)
    part_of = np.zeros(len(V0), int)
    for i, name in enumerate(parts):
        part_of[parts[name]] = i
    names = list(parts)

    def faces_of(*wanted):
        ids = [names.index(w) for w in wanted if w in names]
        return F[np.isin(part_of[F], ids).any(axis=1)]

    lo, hi = q.POSE_RANGES["hip"]
    klo, khi = q.POSE_RANGES["knee"]
    # the two legs of a side (and the tail behind the hind leg), on a grid
    legs = faces_of("leg_fl", "leg_hl", "tail")
    tried = 0
    for hf, kf, hh, kh in itertools.product((lo, 0.0, hi), (klo, khi), (lo, 0.0, hi), (klo, khi)):
        pose = {"leg_fl": (hf, kf), "leg_hl": (hh, kh), "tail": q.POSE_RANGES["tail"][0]}
        if not q.pose_in_range(pose):
            continue
        tried += 1
        V, _, _ = q.quadruped(kind, 3000, pose)
        assert len(q.self_intersections(V, legs)) == 0, pose
    assert tried >= 20
    # on the limit of the crossing rule
    d = q.LEG_CROSSING_LIMIT
    for kf, kh in itertools.product((klo, khi), repeat=2):
        pose = {"leg_fl": (d / 2, kf), "leg_hl": (-d / 2, kh)}
        assert q.pose_in_range(pose)
        V, _, _ = q.quadruped(kind, 3000, pose)
        assert len(q.self_intersections(V, legs)) == 0, pose
    # neck, head and tail at their limits, with the front legs reaching forward
    front = faces_of("torso", "neck", "leg_fl", "leg_fr", "ear_l", "ear_r", "horn_l", "horn_r", "tail")
    for neck, head, tail in itertools.product(q.POSE_RANGES["neck"], q.POSE_RANGES["head"],
                                              q.POSE_RANGES["tail"]):
        pose = {"neck": neck, "head": head, "tail": tail, "leg_fl": (hi, khi), "leg_fr": (hi, klo)}
        V, F2, _ = q.quadruped(kind, 3000, pose)
        assert len(q.self_intersections(V, front)) == 0, pose
        assert q.mesh_stats(V, F2)["min_angle"] > 1.0, pose


def test_presets_are_documented_poses():
    assert q.pose_in_range(q.WALK) and q.pose_in_range(q.GALLOP) and q.pose_in_range(None)
    assert not q.pose_in_range({"neck": 45.0})
    assert not q.pose_in_range({"leg_hr": (0.0, -10.0)})
    assert not q.pose_in_range({"leg_fr": (-20.0, 0.0), "leg_hr": (10.0, 0.0)})


# --- jitter -----------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", KINDS)
def test_jitter_gives_valid_irregular_meshes(kind):
    for pose in (None, q.GALLOP):
        V0, F0, L0 = q.quadruped(kind, 6000, pose, seed=4)
        V, F, L = q.quadruped(kind, 6000, pose, seed=4, jitter=0.35)
        assert np.array_equal(F, F0) and L == L0, "jitter moves vertices only"
        assert_valid_surface(V, F)
        assert len(q.self_intersections(V, F)) == 0
        n0 = np.cross(V0[F[:, 1]] - V0[F[:, 0]], V0[F[:, 2]] - V0[F[:, 0]])
        n1 = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
        assert (np.einsum("ij,ij->i", n0, n1) > 0).all(), "no face folds over"
        move = np.linalg.norm(V - V0, axis=1)
        h = mean_edge(V0, F0)
        assert 0.03 * h < move.mean() < 0.35 * h
        assert move.max() < 0.5 * np.linalg.norm(V0[F0[:, [1, 2, 0]]] - V0[F0], axis=2).max()
    # more irregular than the clean mesh: the spread of edge lengths grows
    e0 = np.linalg.norm(V0[F0[:, [1, 2, 0]]] - V0[F0], axis=2)
    e1 = np.linalg.norm(V[F[:, [1, 2, 0]]] - V[F], axis=2)
    assert np.std(e1 / e1.mean()) > 1.05 * np.std(e0 / e0.mean())


# --- transform and arguments -------------------------------------------------------------

def test_transform_copies():
    V, F, L = q.quadruped("cow", 3000)
    vol = meshes.signed_volume(V, F)
    angle = 0.7
    R = np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1.0]])
    V2, F2 = q.transform(V, F, scale=1e-3, rotation=R, offset=(5.0, -2.0, 1.0))
    assert V2.dtype == np.float64 and F2.dtype == np.int32
    assert np.array_equal(F2, F)
    assert np.isclose(meshes.signed_volume(V2, F2), 1e-9 * vol, rtol=1e-9)
    assert np.allclose(V2, 1e-3 * V @ R.T + [5.0, -2.0, 1.0])
    V3, F3 = q.transform(V, F, inside_out=True)
    assert np.isclose(meshes.signed_volume(V3, F3), -vol)
    report = pm.validate(V3, F3)
    assert report.is_closed_genus0
    assert np.array_equal(F3[:, ::-1], F)


def test_bad_arguments():
    with pytest.raises(ValueError):
        q.quadruped("giraffe")
    with pytest.raises(ValueError):
        q.quadruped("horse", 3000, {"wing": 10.0})
    with pytest.raises(ValueError):
        q.quadruped("horse", 3000, jitter=0.9)
    with pytest.raises(ValueError):
        q.quadruped("horse", 100)
