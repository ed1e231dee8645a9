#!/usr/bin/env python3
"""Share of each atmosphere shader's code that comes from the shared C++/GLSL headers.

Usage: scripts/glsl_share.py [--root DIR] [--min PERCENT]

Counting rule. A shader is assembled from parts (gpu::sky_parts in gpu/src/sky.cpp,
the test's list for shared_check.comp): blocks of the shared headers
libatmo/include/atmosh/atmo/shared/*.glsl.hpp (the lines between ATMOSH_GLSL_BEGIN and
ATMOSH_GLSL_END, which the C++ build compiles too) and hand-written GLSL under
gpu/shaders/. A code line is a line that is neither blank nor only a comment
(`//` or a `/* ... */` line, preprocessor lines count as code). A part pasted twice
(in float and in double) counts once. share = shared code lines / all code lines of
the parts. A shared block counts whole, also where the shader calls only some of its
functions (the driver drops the rest), so the number says how much of the GLSL a
shader is built from is compiled by the CPU build too, and the hand-written count
says how much is not. Hence the lines of a shared block that only one side compiles
are not counted as shared: the conditionals of a block are evaluated for the C++ build
(nothing defined) and for the shader's GLSL (ATMOSH_GLSL and the macros the shader is
assembled with, DEFINES); lines only the GLSL sees (e.g. `#ifdef ATMOSH_GLSL`) count as
hand-written, lines the shader's GLSL does not see (`#ifndef ATMOSH_GLSL`, or the walk
under `#if !defined(ATMOSH_GLSL) || defined(ATMOSH_SKY_TRACE)` in the shaders other
than sky.comp) are not counted.
"""
import argparse
import re
import os
import sys

SHARED = "libatmo/include/atmosh/atmo/shared/"
SKY_PARTS = [SHARED + "geometry.glsl.hpp", SHARED + "lut.glsl.hpp", SHARED + "scatter.glsl.hpp",
             SHARED + "ms_approx.glsl.hpp", SHARED + "view_ray.glsl.hpp", SHARED + "sky_params.glsl.hpp",
             "gpu/shaders/sky_lib.glsl"]
SHADERS = {
    # gpu::sky_pass_parts: the orders block after view_ray, the orders tables' buffers and
    # lookup before sky.comp; assembled with ATMOSH_SKY_TRACE (DEFINES)
    "sky.comp": SKY_PARTS[:5] + [SHARED + "orders.glsl.hpp"] + SKY_PARTS[5:] +
                ["gpu/shaders/sky_orders.glsl", "gpu/shaders/orders_lookup.glsl", "gpu/shaders/sky.comp"],
    "lut_build.comp": SKY_PARTS + ["gpu/shaders/lut_build.comp"],
    "ms_build.comp": SKY_PARTS + ["gpu/shaders/ms_build.comp"],
    "sun_lookup.comp": SKY_PARTS + ["gpu/shaders/sun_lookup.comp"],
    "ozone_check.comp": SKY_PARTS + ["gpu/shaders/ozone_check.comp"],
    "view_ray_check.comp": SKY_PARTS + ["gpu/shaders/view_ray_check.comp"],
    "shared_check.comp": [SHARED + "geometry.glsl.hpp", SHARED + "lut.glsl.hpp", "gpu/shaders/shared_check.comp"],
}
# The successive-orders passes (gpu::build_scattering_orders's orders_parts in gpu/src/orders.cpp).
ORDERS_PARTS = [SHARED + "geometry.glsl.hpp", SHARED + "orders.glsl.hpp", "gpu/shaders/orders_lib.glsl",
                "gpu/shaders/orders_lookup.glsl"]
for _s in ("orders_incoming.comp", "orders_density.comp", "orders_ground.comp", "orders_radiance.comp",
           "orders_log.comp"):
    SHADERS[_s] = ORDERS_PARTS + ["gpu/shaders/" + _s]
# S_1: the sky parts (sun_lookup, phase_value) and the orders block (orders.cpp's single_parts).
SHADERS["orders_single.comp"] = SKY_PARTS[:4] + [SHARED + "orders.glsl.hpp"] + SKY_PARTS[4:] + ["gpu/shaders/orders_single.comp"]


# Macros a shader is assembled with (gpu::render_sky's Program; sky.comp in its full
# form, with the multiple-scattering and orders terms the scene may ask for).
DEFINES = {"sky.comp": {"ATMOSH_SKY_TRACE", "ATMOSH_SKY_MS", "ATMOSH_SKY_ORDERS"}}


def condition(d, defined):
    """Value of the conditional directive d (without '#') with the macros `defined`;
    other names (include guards such as ATMOSH_SHARED_LUT_ONCE) count as undefined."""
    words = d.split()
    if words[0] == "ifdef":
        return words[1] in defined
    if words[0] == "ifndef":
        return words[1] not in defined
    expr = d[len("if"):].split("//")[0]
    expr = re.sub(r"defined\s*\(\s*(\w+)\s*\)", lambda m: str(m.group(1) in defined), expr)
    return bool(eval(expr.replace("||", " or ").replace("&&", " and ").replace("!", " not ")))


def code_lines(path, defines=()):
    """(lines both builds compile, lines only the shader's GLSL sees) of a part: the C++
    build defines nothing, the GLSL build ATMOSH_GLSL and the shader's `defines`."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    if path.endswith(".hpp"):
        begin = next(i for i, l in enumerate(lines) if l.strip().startswith("// ATMOSH_GLSL_BEGIN"))
        end = next(i for i, l in enumerate(lines) if l.strip().startswith("// ATMOSH_GLSL_END"))
        lines = lines[begin + 1:end]
    glsl_env, cpp_env = {"ATMOSH_GLSL", *defines}, set()
    both = glsl_only = 0
    stack = []  # per open conditional: [in GLSL, in C++] of its current branch
    for l in lines:
        s = l.strip()
        if not s or s.startswith("//") or (s.startswith("/*") and s.endswith("*/")):
            continue
        d = s[1:].strip() if s.startswith("#") else ""
        # A conditional's own directives belong to the region around it.
        around = stack[:-1] if (d.startswith("else") or d.startswith("endif")) else stack
        in_glsl = all(g for g, _ in around)
        in_cpp = path.endswith(".hpp") and all(c for _, c in around)
        if d.startswith("if"):
            stack.append([condition(d, glsl_env), condition(d, cpp_env)])
        elif d.startswith("else") and stack:
            stack[-1] = [not stack[-1][0], not stack[-1][1]]
        elif d.startswith("endif") and stack:
            stack.pop()
        if in_glsl and in_cpp:
            both += 1
        elif in_glsl:
            glsl_only += 1
    return both, glsl_only


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    ap.add_argument("--min", type=float, default=0.0, help="fail if a shader's share is below this percentage")
    args = ap.parse_args()
    print("| shader | shared code lines | hand-written code lines | shared |")
    print("|---|---|---|---|")
    worst = 100.0
    for name, parts in SHADERS.items():
        shared = hand = 0
        for p in dict.fromkeys(parts):  # each part once
            path = os.path.join(args.root, p)
            if not os.path.exists(path):
                continue
            n, glsl_only = code_lines(path, DEFINES.get(name, ()))
            if p.startswith(SHARED):
                shared += n
                hand += glsl_only
            else:
                hand += n + glsl_only
        share = 100.0 * shared / (shared + hand)
        worst = min(worst, share)
        print(f"| {name} | {shared} | {hand} | {share:.1f} % |")
    if worst < args.min:
        print(f"lowest share {worst:.1f} % is below {args.min} %", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
