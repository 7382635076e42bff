#!/usr/bin/env python3
"""One residual per dimension (docs/DESIGN.md "Residuals"): the pose-graph residuals r = ρ(z⁻¹ T_i⁻¹ T_j) and
r = T⁻¹ l − z are written in engine/graph/residuals.{hpp,cpp} and nowhere else. Outside those two files, no engine
source (unit tests aside) defines a function named *edge*_residual, *landmark*_residual, linearize_edge or
linearize_landmark, composes an inverse, another inverse and a third pose (`a.inverse() * b.inverse() * c`, the
shape of z⁻¹ T_i⁻¹ T_j), or converts a quaternion to a rotation vector with Ceres (`QuaternionToAngleAxis`, the 3D residual's
rotation part). Usage: check_residuals.py REPO; exit 1 and one line per finding."""
import os
import re

from sources import engine_sources, run

HOME = {os.path.join("engine", "graph", "residuals.hpp"), os.path.join("engine", "graph", "residuals.cpp")}
DEFINITION = re.compile(r"^(?:template\s*<[^>]*>\s*)?[A-Za-z_][\w:<>, ]*[\s&*]"
                        r"(\w*(?:edge|landmark)\w*_residual|linearize_edge|linearize_landmark)\s*\([^;]*$")
RULES = [
    (re.compile(r"inverse\(\)\s*\*\s*\(?\s*[A-Za-z_][\w\[\]\.]*\.inverse\(\)\s*\*\s*[A-Za-z_(]"),
     "composes z⁻¹ T_i⁻¹ T_j: call graph::edge_residual"),
    (re.compile(r"QuaternionToAngleAxis"), "a quaternion's rotation vector: the 3D residual is graph::edge_residual"),
]


def check(repo):
    problems = []
    for path in engine_sources(repo):
        rel = os.path.relpath(path, repo)
        if rel in HOME:
            continue
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                code = line.split("//", 1)[0]
                m = DEFINITION.match(code)
                if m:
                    problems.append(f"{rel}:{number}: defines {m.group(1)}; the residuals live in graph/residuals")
                for rule, why in RULES:
                    if rule.search(code):
                        problems.append(f"{rel}:{number}: {why}")
    return problems


if __name__ == "__main__":
    run(check)
