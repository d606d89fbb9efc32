"""The knee's landmarks on the Visible Human Female's right leg (issue #35), in plain
Python like visible_human_geometry.py: the points and circles the knee's mechanism needs
(the flexion axis, the trochlear groove, the patella's articular ridge, the patellar
tendon's ends, the hip and the ankle), fitted to the segmented surfaces by the rules
below and written to `landmarks.csv` (data frame, mm).

**Knee frame** (the one the knee study works in, `crates/studies/src/knee/anatomy/
dimensions.rs`): origin midway between the centres of the two posterior condyles, z
lateral along the line through them (the geometric centre axis, a flexion axis within a
few millimetres of the transepicondylar one), y proximal along the mechanical axis (origin
to the femoral head's centre) made normal to z, x = y × z anterior.

- `medial_condyle`, `lateral_condyle`: least-squares spheres (Kåsa) through the distal
  femoral cartilage's vertices medial (lateral) of its mean, posterior of the 40th
  percentile of their anterior coordinate (the posterior condyles' flexion facets);
- `femoral_head`: the sphere through the femoral head's cartilage (the hip centre);
- `trochlear_groove`: the circle through the groove's floor in the sagittal plane (knee
  frame): for each direction at an angle a = −40°, −35°, …, 10° from x towards y (about
  the flexion axis), the cartilage vertices within 2.5° of it and anterior of x = −5 mm,
  their outer envelope (the largest radial distance) in 2 mm slices of z, and the floor
  as the smallest envelope over the middle 60 % of the slices; the circle's centre is
  written at the floor points' mean z;
- `patellar_ridge`: the circle through the patella cartilage's posterior-most vertex in
  each 2 mm slice of y (knee frame), 3 mm in from either end, in the sagittal plane;
  centre at those vertices' mean z;
- `patella_apex`: the patella's most distal vertex (knee frame y), where the patellar
  tendon arises; `patella_base`: its most proximal vertex;
- `tibial_tuberosity`: the tibia's most anterior vertex between 25 and 70 mm below the
  flexion axis, where the patellar tendon inserts;
- `ankle`: the centroid of the distal tibial cartilage's vertices (the pin of the
  closed-chain squat).
"""

import math

import visible_human_geometry as geo

CONDYLE_POSTERIOR_PERCENTILE = 40.0
GROOVE_ANGLES = [-40.0 + 5.0 * k for k in range(11)]  # degrees, −40 … 10
GROOVE_HALF_WIDTH = 2.5  # degrees
GROOVE_ANTERIOR_OF = -5.0  # mm
SLICE = 2.0  # mm
GROOVE_MIDDLE = (0.2, 0.8)
RIDGE_END_MARGIN = 3.0  # mm
TUBEROSITY_BELOW = (25.0, 70.0)  # mm below the flexion axis


def percentile(values, p):
    """The p-th percentile of `values` by linear interpolation between order statistics."""
    ordered = sorted(values)
    position = (len(ordered) - 1) * p / 100.0
    low = math.floor(position)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (position - low)


class KneeFrame:
    """The knee frame (module documentation): `to_knee(p)` maps a data point [mm] to
    knee-frame coordinates [mm]."""

    def __init__(self, medial, lateral, hip):
        self.origin = geo.scale(geo.add(medial, lateral), 0.5)
        self.z = geo.normalize(geo.sub(lateral, medial))
        m = geo.sub(hip, self.origin)
        self.y = geo.normalize(geo.sub(m, geo.scale(self.z, geo.dot(m, self.z))))
        self.x = geo.cross(self.y, self.z)

    def to_knee(self, p):
        d = geo.sub(p, self.origin)
        return (geo.dot(d, self.x), geo.dot(d, self.y), geo.dot(d, self.z))

    def to_data(self, q):
        return geo.add(self.origin, geo.add(geo.scale(self.x, q[0]), geo.add(
            geo.scale(self.y, q[1]), geo.scale(self.z, q[2]))))


def condyles(points):
    """The medial and lateral posterior condyles' spheres (centre, radius)."""
    mean_x = sum(p[0] for p in points) / len(points)
    spheres = []
    for medial in (True, False):
        side = [p for p in points if (p[0] < mean_x) == medial]
        cut = percentile([p[1] for p in side], CONDYLE_POSTERIOR_PERCENTILE)
        spheres.append(geo.fit_sphere([p for p in side if p[1] < cut]))
    return spheres


def groove(frame, points):
    """The trochlear groove's floor points (knee frame) and their circle ((x, y), r)."""
    knee = [frame.to_knee(p) for p in points]
    anterior = [q for q in knee if q[0] > GROOVE_ANTERIOR_OF]
    floor = []
    for angle in GROOVE_ANGLES:
        u = (math.cos(math.radians(angle)), math.sin(math.radians(angle)))
        envelope = {}
        for q in anterior:
            if abs(math.degrees(math.atan2(q[1], q[0])) - angle) >= GROOVE_HALF_WIDTH:
                continue
            radial = q[0] * u[0] + q[1] * u[1]
            key = round(q[2] / SLICE)
            if key not in envelope or radial > envelope[key][0]:
                envelope[key] = (radial, q)
        slices = sorted(envelope)
        if len(slices) < 8:
            continue
        low, high = (int(f * len(slices)) for f in GROOVE_MIDDLE)
        floor.append(min((envelope[k] for k in slices[low:high]), key=lambda e: e[0])[1])
    centre, radius = geo.fit_circle([(q[0], q[1]) for q in floor])
    return floor, centre, radius


def ridge(frame, points):
    """The patella's articular ridge: posterior-most points (knee frame) and circle."""
    knee = [frame.to_knee(p) for p in points]
    lowest, highest = min(q[1] for q in knee), max(q[1] for q in knee)
    profile = []
    y = lowest + RIDGE_END_MARGIN
    while y < highest - RIDGE_END_MARGIN:
        near = [q for q in knee if abs(q[1] - y) < SLICE / 2]
        if near:
            profile.append(min(near, key=lambda q: q[0]))
        y += SLICE
    centre, radius = geo.fit_circle([(q[0], q[1]) for q in profile])
    return profile, centre, radius


def knee_landmarks(data):
    """Every landmark as (name, point in the data frame [mm], radius [mm] or None)."""
    def surface(name):
        return geo.read_binary_stl(data / f"VHF_Right_{name}_smooth.stl")[0]

    (medial, medial_r), (lateral, lateral_r) = condyles(surface("Cartilage_FemurDistal"))
    head, head_r = geo.fit_sphere(surface("Cartilage_FemurHead"))
    frame = KneeFrame(medial, lateral, head)
    floor, groove_centre, groove_r = groove(frame, surface("Cartilage_FemurDistal"))
    groove_z = sum(q[2] for q in floor) / len(floor)
    profile, ridge_centre, ridge_r = ridge(frame, surface("Cartilage_Patella"))
    ridge_z = sum(q[2] for q in profile) / len(profile)
    patella = [frame.to_knee(p) for p in surface("Bone_Patella")]
    tibia = [frame.to_knee(p) for p in surface("Bone_Tibia")]
    band = [q for q in tibia if -TUBEROSITY_BELOW[1] <= q[1] <= -TUBEROSITY_BELOW[0]]
    ankle_points = surface("Cartilage_TibiaDistal")
    ankle = geo.scale(
        tuple(sum(p[k] for p in ankle_points) for k in range(3)), 1.0 / len(ankle_points))
    return [
        ("medial_condyle", medial, medial_r),
        ("lateral_condyle", lateral, lateral_r),
        ("femoral_head", head, head_r),
        ("trochlear_groove", frame.to_data((*groove_centre, groove_z)), groove_r),
        ("patellar_ridge", frame.to_data((*ridge_centre, ridge_z)), ridge_r),
        ("patella_apex", frame.to_data(min(patella, key=lambda q: q[1])), None),
        ("patella_base", frame.to_data(max(patella, key=lambda q: q[1])), None),
        ("tibial_tuberosity", frame.to_data(max(band, key=lambda q: q[0])), None),
        ("ankle", ankle, None),
    ]


def write_landmarks(path, landmarks):
    """`landmarks.csv`: landmark, x_mm, y_mm, z_mm (data frame), radius_mm (or empty)."""
    with open(path, "w", encoding="ascii") as f:
        f.write("landmark,x_mm,y_mm,z_mm,radius_mm\n")
        for name, p, radius in landmarks:
            r = "" if radius is None else f"{radius:.4f}"
            f.write(f"{name},{p[0]:.4f},{p[1]:.4f},{p[2]:.4f},{r}\n")
