#!/usr/bin/env python3
"""Run CONTACT (E. Vollebregt's open-source solver of Kalker's exact theory, Apache-2.0) on
Hertzian steady-rolling cases and print its total forces as CSV: the reference data of
tests/data/contact/ that kecsim's exact solver and creep models are tested against.

CONTACT is not part of kecsim and this script copies none of it: it writes CONTACT's input files
(the format of its user guide, section 5) and reads the totals from its `.out` file. Build CONTACT
from github.com/eve70a/CONTACT (v25.2; with gfortran, its Intel-Fortran-only constructs ported in
eight files, or with Intel Fortran as its makefile expects), then

    python3 scripts/contact_reference.py --contact /path/to/contact_linux64 CASES.csv > OUT.csv

CASES.csv has the columns  n_n,a_mm,b_mm,xi,eta,phi_per_m,mu[,mx,my]  (the patch's semi-axes a
along the rolling direction and b across, the creepages, the spin in 1/m, the friction; mx, my
the elements over the ellipse's length and width, default 40). The output repeats them and adds
CONTACT's fx_n, fy_n, mz_n_m (forces on the wheel, kecsim's sign convention, which is CONTACT's:
a positive creepage gives a negative force), its numbers of elements in adhesion and slip, the
curvatures a1, b1 (1/m) of its Hertzian gap h = a1 x^2 + b1 y^2, its potential contact area
[-grid_x, grid_x] x [-grid_y, grid_y] mm of grid_mx x grid_my elements (its normal problem is solved
on that grid), and its version. G = 82 GPa and nu = 0.28 (steel) unless --g-gpa / --poisson say otherwise.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

HEADER = """ 3 MODULE
  203100     P-B-T-N-F-S        PVTIME, BOUND , TANG  , NORM , FORCE, STRESS
  022020     L-D-C-M-Z-E        FRCLAW, DISCNS, INFLCF, MATER, RZNORM, EXRHS
 0000341   H-G-I-A-O-W-R  HEAT, GAUSEI, IESTIM, MATFIL, OUTPUT, FLOW, RETURN
   200   400    5    1      1e-7    MAXGS , MAXIN , MAXNR , MAXOUT, EPS
"""


def case_text(row, g_nmm2, nu):
    n = float(row["n_n"])
    a, b = float(row["a_mm"]), float(row["b_mm"])
    xi, eta = float(row["xi"]), float(row["eta"])
    phi = float(row["phi_per_m"]) * 1e-3  # 1/mm
    mu = float(row["mu"])
    mx = int(row.get("mx") or 40)
    my = int(row.get("my") or 40)
    # The potential contact area is SCALE times the ellipse's box: mx elements over 2a means
    # mx + 4 over 2a (mx + 4)/mx.
    scale_x = (mx + 4) / mx
    scale_y = (my + 4) / my
    scale = max(scale_x, scale_y)
    return (
        HEADER
        + f" {n:.6e} {xi:.6e} {eta:.6e} {phi:.6e}    FN, CKSI, CETA, CPHI\n"
        + f" {mu:.6f} {mu:.6f}    FSTAT, FKIN\n"
        + " 0.000  0.400  30000.    CHI, DQ, VELOC\n"
        + f" {nu:.4f} {nu:.4f} {g_nmm2:.1f} {g_nmm2:.1f}    POISS 1,2,  GG 1,2\n"
        + " -3    IPOTCN\n"
        + f" {round(mx * scale)} {round(my * scale)} {a:.6f} {b:.6f} {scale:.6f}    MX,MY,AA,BB,SCALE\n\n"
    )


def parse(out_text):
    rows = []
    for chunk in out_text.split(" Case ")[1:]:
        f = re.search(
            r"FN\s+FX\s+FY\s+MZ\s+ELAST\.EN\.\s+FRIC\.POWER\s*\n\s*(\S+)\s+(\S+)\s+(\S+)\s+(\S+)", chunk
        )
        s = re.search(r"NPOT\s+NCON\s+NADH\s+NSLIP.*\n\s*(\d+)\s+(\d+)\s+(\d+)\s+(\d+)", chunk)
        c = re.search(r"THE CURVATURES A1,B1 ARE:\s+(\S+)\s+(\S+)", chunk)
        g = re.search(r"POTENTIAL CONTACT, SCALE:\s+(\S+)\s+(\S+)", chunk)
        d = re.search(r"DISCRETISATION MX,MY, DX,DY:\s+(\d+)\s+(\d+)", chunk)
        if not (f and s and c and g and d):
            raise SystemExit("cannot read a case's totals from CONTACT's output")
        fn, fx, fy, mz = (float(v) for v in f.groups())
        rows.append((fx, fy, mz * 1e-3, int(s.group(3)), int(s.group(4)),
                     float(c.group(1)) * 1e3, float(c.group(2)) * 1e3,  # 1/mm -> 1/m
                     -float(g.group(1)), -float(g.group(2)), int(d.group(1)), int(d.group(2))))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cases")
    ap.add_argument("--contact", required=True, help="CONTACT's executable (contact_linux64)")
    ap.add_argument("--g-gpa", type=float, default=82.0)
    ap.add_argument("--poisson", type=float, default=0.28)
    args = ap.parse_args()
    with open(args.cases) as f:
        cases = list(csv.DictReader(f))
    g = args.g_gpa * 1e3
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "ref.inp"), "w") as f:
            for row in cases:
                f.write(case_text(row, g, args.poisson))
        subprocess.run(
            [os.path.abspath(args.contact), "2", "ref"], cwd=d, check=True,
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )
        out = open(os.path.join(d, "ref.out")).read()
    version = re.search(r"\$Revision: (\d+)", out)
    results = parse(out)
    if len(results) != len(cases):
        raise SystemExit(f"CONTACT solved {len(results)} of {len(cases)} cases")
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["n_n", "a_mm", "b_mm", "xi", "eta", "phi_per_m", "mu", "mx", "my",
                "fx_n", "fy_n", "mz_n_m", "n_adhesion", "n_slip",
                "a1_per_m", "b1_per_m", "grid_x_mm", "grid_y_mm", "grid_mx", "grid_my", "contact_revision"])
    for row, (fx, fy, mz, na, ns, a1, b1, gx, gy, gmx, gmy) in zip(cases, results):
        w.writerow([row["n_n"], row["a_mm"], row["b_mm"], row["xi"], row["eta"], row["phi_per_m"],
                    row["mu"], row.get("mx") or 40, row.get("my") or 40,
                    f"{fx:.6g}", f"{fy:.6g}", f"{mz:.6g}", na, ns,
                    f"{a1:.6g}", f"{b1:.6g}", f"{gx:.6g}", f"{gy:.6g}", gmx, gmy,
                    version.group(1) if version else "?"])


if __name__ == "__main__":
    main()
