#!/usr/bin/env python3
"""Generates mapc's EPSG table and the PROJ check points from PROJ's own database.

    python3 -m venv venv && venv/bin/pip install pyproj
    venv/bin/python tools/crs/gen_epsg.py frontend/data/epsg.txt tests/data/proj_epsg_points.csv

For every projected CRS of the EPSG database, the table holds what `pyproj.Transformer.from_crs(
"EPSG:4326", code, always_xy=True)` (PROJ's default transformation, no grid files) would
choose from: every instantiable candidate operation in PROJ's order, with its area of use,
accuracy and PROJ pipeline steps. Steps are interned (`S` lines) because thousands of CRSs
share datum shifts. A CRS whose axes are not in metres gets its unit (mapc refuses it).

The points file holds, per metre CRS, lon/lat points in its area of use and in each
candidate's area, with the easting/northing PROJ gives for them: the oracle of
tests/proj_epsg.rs. Nothing in either file is written by hand.
"""
import csv
import sys
import warnings

import pyproj
from pyproj import CRS, Transformer
from pyproj.database import get_database_metadata, query_crs_info
from pyproj.enums import PJType
from pyproj.transformer import TransformerGroup

warnings.filterwarnings("ignore")


def steps_of(definition):
    """PROJ pipeline definition -> list of step strings (`[inv ]proj=... k=v ...`)."""
    parts = definition.split(" step ")
    if not parts[0].startswith("proj=pipeline"):
        return [definition]  # a single operation
    return [p.strip() for p in parts[1:]]


def inset_points(west, south, east, north):
    """The centre of a lon/lat box and two points inset from opposite corners."""
    if west > east:  # crosses the antimeridian
        east += 360.0
    pts = []
    for fx, fy in ((0.5, 0.5), (0.25, 0.3), (0.7, 0.75)):
        lon = west + (east - west) * fx
        if lon > 180.0:
            lon -= 360.0
        pts.append((round(lon, 6), round(south + (north - south) * fy, 6)))
    return pts


def main(table_path, points_path):
    infos = query_crs_info(
        auth_name="EPSG", pj_types=[PJType.PROJECTED_CRS], allow_deprecated=True
    )
    step_ids = {}
    out = []
    rows = []
    for info in sorted(infos, key=lambda i: int(i.code)):
        code = int(info.code)
        try:
            crs = CRS.from_epsg(code)
        except pyproj.exceptions.CRSError as e:
            out.append(f"C {code} ! PROJ cannot build it: {str(e).splitlines()[0]}")
            continue
        units = {a.unit_name for a in crs.axis_info}
        if units != {"metre"}:
            unit = sorted(units)[0] if units else "no axes"
            out.append(f"C {code} u {unit}")
            continue
        try:
            group = TransformerGroup(4326, code, always_xy=True)
            cands = group.transformers
        except Exception:  # pyproj fails on a few CRSs without a defined projection
            cands = []
        if not cands:
            out.append(f"C {code} ! PROJ has no transformation from WGS 84 to it")
            continue
        boxes = []
        a = crs.area_of_use
        # A few deprecated CRSs have a placeholder area (-1000, ...): then the candidates'.
        if a is not None and -180 <= a.west <= 180 and -90 <= a.south <= 90:
            boxes.append((a.west, a.south, a.east, a.north))
        # TransformerGroup misses some operations `from_crs` chooses (e.g. PD/83 via ETRS89
        # for EPSG:3396): add what `from_crs` used at the CRS's area, before the others, as
        # PROJ sorts known-accuracy operations before ballpark ones.
        transformer = Transformer.from_crs(4326, code, always_xy=True)
        if boxes:
            defs = {tr.definition for tr in cands}
            for lon, lat in inset_points(*boxes[0]):
                transformer.transform(lon, lat)
                used = transformer.get_last_used_operation()
                if used is not None and used.definition not in defs:
                    defs.add(used.definition)
                    cands = [used] + list(cands)
        out.append(f"C {code} m")
        for tr in cands:
            aou = tr.area_of_use
            if aou is None:
                bbox, area_name = (-180.0, -90.0, 180.0, 90.0), ""
            else:
                bbox, area_name = (aou.west, aou.south, aou.east, aou.north), aou.name or ""
            flags = ""
            if "- offshore" in area_name:
                flags += "o"
            if area_name in ("", "unknown"):
                flags += "u"
            ids = []
            for s in steps_of(tr.definition):
                if s not in step_ids:
                    step_ids[s] = len(step_ids)
                ids.append(str(step_ids[s]))
            acc = tr.accuracy if tr.accuracy is not None else -1.0
            out.append(
                "O {} {} {} {} {} {} {}".format(
                    *(repr(float(v)) for v in bbox), repr(float(acc)), flags or "-", ",".join(ids)
                )
            )
        # Check points: the CRS's area of use and every candidate's own area (not the whole
        # world of a ballpark operation when the CRS has no area of its own).
        crs_has_area = bool(boxes)
        if not crs_has_area:
            # No area at all (a few deprecated CRSs with only a ballpark operation): around
            # the projection's origin.
            lon0 = lat0 = None
            for prm in crs.coordinate_operation.params if crs.coordinate_operation else []:
                if prm.unit_name != "degree":
                    continue
                if lon0 is None and "Longitude" in prm.name:
                    lon0 = prm.value
                if lat0 is None and "Latitude" in prm.name:
                    lat0 = prm.value
            if lon0 is not None and lat0 is not None:
                boxes.append((lon0 - 1, max(lat0 - 1, -89.0), lon0 + 1, min(lat0 + 1, 89.0)))
        for tr in cands:
            if tr.area_of_use is not None:
                a = tr.area_of_use
                b = (a.west, a.south, a.east, a.north)
                if not crs_has_area and b == (-180.0, -90.0, 180.0, 90.0):
                    continue
                if boxes and b[0] <= b[2] and boxes[0][0] <= boxes[0][2]:
                    # Only the part inside the CRS's own area: far outside it a projection
                    # means nothing (PROJ and mapc may both give numbers, or fail).
                    c = boxes[0]
                    b = (max(b[0], c[0]), max(b[1], c[1]), min(b[2], c[2]), min(b[3], c[3]))
                    if b[0] >= b[2] or b[1] >= b[3]:
                        continue
                if b not in boxes:
                    boxes.append(b)
        seen = set()
        for box in boxes[:4]:
            for lon, lat in inset_points(*box):
                if (lon, lat) in seen:
                    continue
                seen.add((lon, lat))
                e, n = transformer.transform(lon, lat)
                if e == float("inf") or n == float("inf") or e != e or n != n:
                    continue
                rows.append((code, lon, lat, repr(e), repr(n)))

    meta = (
        f"# EPSG {get_database_metadata('EPSG.VERSION')}, PROJ {pyproj.proj_version_str}, "
        f"pyproj {pyproj.__version__}; generated by tools/crs/gen_epsg.py, do not edit\n"
    )
    with open(table_path, "w") as f:
        f.write(meta)
        for s, i in step_ids.items():
            f.write(f"S {i} {s}\n")
        for line in out:
            f.write(line + "\n")
    with open(points_path, "w", newline="") as f:
        f.write(meta)
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["code", "lon", "lat", "easting", "northing"])
        w.writerows(rows)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
