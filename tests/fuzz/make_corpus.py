#!/usr/bin/env python3
"""Writes a corpus of malformed scene files, each built from a shipped scene (configs/*.toml),
into OUT_DIR, with an index OUT_DIR/classes.tsv: file, class, description, expect.

Every file is invalid on purpose, and for one reason that the description names (the key and
the value it sets). `expect` says what the refusal must show besides the file's path:
  line        "PATH:N:" (a line number)
  key:K       "PATH:N: key 'K" (the line and the key, K a prefix of the dotted key)
  file        the path alone: files over the 1 MiB scene limit or with NUL bytes are refused
              whole, before parsing, so there is no line to name
The files are checked here before they are written (Python's tomllib): a scene whose fault is
its meaning (a value, a name, a count) must be valid TOML with the faulty value in place, so that
it cannot be refused for some other, accidental reason; a syntax error or a TOML duplicate must
not be valid TOML; a truncation must lose (part of) a required key of the first [[fluid]].

Deterministic: the same seed and configs give the same bytes. Standard library only.

Usage: make_corpus.py OUT_DIR [--seed N] [--configs DIR] [--no-huge] [--huge-mb MB]
The huge files (50 MB each by default) are written only here, at test time; never commit them.
"""

import argparse
import math
import os
import random
import re
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG_NAMES = ["boiling", "dam_break", "diffusion", "lava_lamp", "pour_glass", "two_fluids_mixed", "water_oil"]

# --------------------------------------------------------------------------------------------
# TOML values and text edits


class Raw(str):
    """TOML text written as is (a date, an inline table, broken syntax)."""


def tstr(s):
    out = ['"']
    for ch in s:
        o = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif o < 0x20 or o == 0x7F:
            out.append("\\u%04x" % o)
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def tv(v):
    if isinstance(v, Raw):
        return str(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return tstr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(tv(x) for x in v) + "]"
    raise TypeError(repr(v))


def code_part(line):
    """The line up to a comment (a '#' outside strings)."""
    q = None
    i = 0
    while i < len(line):
        c = line[i]
        if q:
            if q == '"' and c == "\\":
                i += 2
                continue
            if c == q:
                q = None
        elif c in "\"'":
            q = c
        elif c == "#":
            return line[:i]
        i += 1
    return line


HEADER = re.compile(r"^\s*(\[\[|\[)\s*([^\[\]]+?)\s*(\]\]|\])\s*$")


def short(v, n=60):
    s = tv(v)
    if len(s) <= n:
        return s
    return s[: n - 12] + ('..." (%d characters)' % len(v) if isinstance(v, str) and not isinstance(v, Raw) else "...")


class Doc:
    def __init__(self, name, text):
        self.name = name
        self.lines = text.split("\n")

    def clone(self):
        d = Doc(self.name, "")
        d.lines = list(self.lines)
        return d

    def text(self):
        return "\n".join(self.lines)

    def headers(self):
        out = []
        for i, line in enumerate(self.lines):
            m = HEADER.match(code_part(line))
            if m:
                out.append((i, m.group(2).replace(" ", ""), m.group(1) == "[["))
        return out

    def section(self, sec, idx=0):
        """(header line, end line) of the idx-th table `sec`; header -1 for the top level."""
        hs = self.headers()
        if sec == "":
            return -1, hs[0][0] if hs else len(self.lines)
        found = [k for k, h in enumerate(hs) if h[1] == sec]
        if idx >= len(found):
            raise KeyError("%s: no table [%s] #%d" % (self.name, sec, idx))
        k = found[idx]
        return hs[k][0], hs[k + 1][0] if k + 1 < len(hs) else len(self.lines)

    def key_line(self, sec, key, idx=0):
        s, e = self.section(sec, idx)
        pat = re.compile(r"^\s*" + re.escape(key) + r"\s*=")
        for i in range(s + 1, e):
            if pat.match(self.lines[i]):
                return i
        return None

    def ensure_effect(self, sec):
        """Appends an empty [effects.X] the scene leaves out (the shipped scenes on DFSPH have no
        [effects.pressure]), so that its keys can be mutated."""
        if sec.startswith("effects.") and not any(h[1] == sec for h in self.headers()):
            self.lines.append("[%s]" % sec)
        return self

    def set(self, sec, key, value, idx=0):
        """Sets (or adds) `key = value` in a table; the line's comment goes."""
        self.ensure_effect(sec)
        li = self.key_line(sec, key, idx)
        text = "%s = %s" % (key, tv(value))
        if li is None:
            s, _ = self.section(sec, idx)
            self.lines.insert(s + 1, text)
        else:
            self.lines[li] = text
        return self

    def replace_key_line(self, sec, key, text, idx=0):
        li = self.key_line(sec, key, idx)
        if li is None:
            raise KeyError("%s: no %s in [%s]" % (self.name, key, sec))
        self.lines[li] = text
        return self

    def delete(self, sec, key, idx=0):
        li = self.key_line(sec, key, idx)
        if li is not None:
            del self.lines[li]
        return self

    def add_line(self, sec, text, idx=0):
        self.ensure_effect(sec)
        s, _ = self.section(sec, idx)
        self.lines.insert(s + 1, text)
        return self

    def replace_header(self, sec, text, idx=0):
        s, _ = self.section(sec, idx)
        self.lines[s] = text
        return self

    def append(self, block):
        if self.lines and self.lines[-1] == "":
            self.lines.pop()
        self.lines.extend(block.split("\n"))
        self.lines.append("")
        return self


def table_text(header, d, array=True):
    lines = [("[[%s]]" if array else "[%s]") % header]
    for k, v in d.items():
        lines.append("%s = %s" % (k, tv(v)))
    return "\n".join(lines)


def get_path(doc, path):
    v = doc
    for p in path:
        v = v[p]
    return v


def same(a, b):
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    if isinstance(a, (list, tuple)) or isinstance(b, (list, tuple)):
        return (isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)) and len(a) == len(b)
                and all(same(x, y) for x, y in zip(a, b)))
    if isinstance(a, (bool, str)) or isinstance(b, (bool, str)):
        return type(a) == type(b) and a == b
    return a == b


def strings_in(v):
    if isinstance(v, str):
        yield v
    elif isinstance(v, dict):
        for k, x in v.items():
            yield from strings_in(x)
    elif isinstance(v, list):
        for x in v:
            yield from strings_in(x)


# --------------------------------------------------------------------------------------------
# The corpus


class Corpus:
    def __init__(self, out):
        self.out = out
        self.entries = []  # (file, class, description, expect)

    def add(self, cls, config, desc, data, expect="line", check="valid", sets=(), post=None):
        """check: 'valid' (valid TOML, with each (path, value) of `sets` in place, and `post(doc)`
        true), 'invalid' (not valid TOML), 'truncated' (see truncations) or 'none'."""
        if isinstance(data, str):
            data = data.encode("utf-8", "surrogatepass")
        name = "%04d_%s_%s.toml" % (len(self.entries), cls, config or "none")
        # Whole-file refusals have no line or key: a file over multifluid's 1 MiB scene limit, or
        # one with NUL bytes (not a text file), is refused before it is parsed.
        if len(data) > (1 << 20) or b"\0" in data:
            expect = "file"
        if check == "valid":
            try:
                doc = tomllib.loads(data.decode("utf-8"))
            except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
                raise SystemExit("make_corpus: %s (%s) should be valid TOML: %s" % (name, desc, e))
            for path, value in sets:
                got = get_path(doc, path)
                if not same(got, value):
                    raise SystemExit("make_corpus: %s: %r is %r, expected %r" % (name, path, got, value))
            if post and not post(doc):
                raise SystemExit("make_corpus: %s (%s): post-check failed" % (name, desc))
        elif check == "invalid":
            try:
                tomllib.loads(data.decode("utf-8"))
            except (tomllib.TOMLDecodeError, UnicodeDecodeError):
                pass
            else:
                raise SystemExit("make_corpus: %s (%s) should not be valid TOML" % (name, desc))
        elif callable(check):
            if not check(data):
                raise SystemExit("make_corpus: %s (%s): check failed" % (name, desc))
        assert "\t" not in desc and "\n" not in desc, desc
        with open(os.path.join(self.out, name), "wb") as f:
            f.write(data)
        self.entries.append((name, cls, ("%s: %s" % (config, desc)) if config else desc, expect))

    def write_index(self):
        with open(os.path.join(self.out, "classes.tsv"), "w", encoding="utf-8") as f:
            f.write("file\tclass\tdescription\texpect\n")
            for e in self.entries:
                f.write("\t".join(e) + "\n")


class Configs:
    def __init__(self, directory):
        self.text = {}
        self.doc = {}
        for n in CONFIG_NAMES:
            with open(os.path.join(directory, n + ".toml"), encoding="utf-8") as f:
                self.text[n] = f.read()
            self.doc[n] = tomllib.loads(self.text[n])

    def edit(self, name):
        return Doc(name, self.text[name])


def is_array_part(parts, k):
    """Whether parts[k] of a table path names an array of tables: [[phase]], [[fluid]], [[solid]]
    at the top, the lists of effects ([[effects.NAME.LIST]])."""
    return (k == 0 and parts[0] in ("phase", "fluid", "solid")) or (k == 2 and parts[0] == "effects")


def set1(c, cfg, sec, key, value, idx=0):
    """A Doc of `cfg` with one key set, and the tomllib path of it."""
    d = c.edit(cfg).set(sec, key, value, idx)
    parts = [p for p in sec.split(".") if p]
    tp = []
    for k, part in enumerate(parts):
        tp.append(part)
        if is_array_part(parts, k):
            tp.append(idx)
    tp.append(key)
    return d, tuple(tp)


def dotted(sec, key, idx=0):
    """The key as the scene reader names it: phase[0].stiffness, effects.x.source[1].max."""
    parts = [p for p in sec.split(".") if p]
    out = [part + ("[%d]" % idx if is_array_part(parts, k) else "") for k, part in enumerate(parts)]
    out.append(key)
    return ".".join(out)


def one(corpus, c, cls, cfg, sec, key, value, idx=0, note="", expect=None, check="valid"):
    d, path = set1(c, cfg, sec, key, value, idx)
    k = dotted(sec, key, idx)
    desc = "%s = %s%s" % (k, short(value), (" (" + note + ")") if note else "")
    corpus.add(cls, cfg, desc, d.text(), expect=expect or "key:" + k, check=check,
               sets=[(path, value)] if check == "valid" and not isinstance(value, Raw) else [])


# --------------------------------------------------------------------------------------------
# Classes measured to fail today (accepted by validate, then a crash, a hang or nothing to run)


def gen_crashes(corpus, c, rng):
    for cfg in CONFIG_NAMES:
        one(corpus, c, "crash_spacing", cfg, "solver", "particle_spacing", 1e-4, expect="line",
            note="billions of particles: std::bad_alloc")
    for cfg in ["dam_break", "lava_lamp", "water_oil"]:
        one(corpus, c, "crash_spacing", cfg, "solver", "particle_spacing", 2e-5, expect="line",
            note="near the lower bound 1e-5")

    # Many solids: copies of the scene's own first solid, each with its own name.
    for cfg, n in [("dam_break", 2000), ("pour_glass", 2000), ("two_fluids_mixed", 2500), ("lava_lamp", 2000),
                   ("diffusion", 5000)]:
        d = c.edit(cfg)
        s0 = dict(c.doc[cfg]["solid"][0])
        blocks = []
        for k in range(n):
            s = dict(s0)
            s["name"] = "%s_copy%d" % (s0["name"], k)
            blocks.append(table_text("solid", s))
        d.append("\n".join(blocks))
        corpus.add("crash_solids", cfg, "%d more [[solid]] entries (copies of solid[0] '%s', named %s_copy0..%d)"
                   % (n, s0["name"], s0["name"], n - 1), d.text(), expect="line",
                   post=lambda doc, n=n, base=len(c.doc[cfg]["solid"]): len(doc["solid"]) == base + n)

    # Many fluid blocks: copies of the scene's first block.
    for cfg, n in [("dam_break", 3000), ("two_fluids_mixed", 3000), ("water_oil", 3000), ("pour_glass", 3000),
                   ("lava_lamp", 4000)]:
        d = c.edit(cfg)
        f0 = c.doc[cfg]["fluid"][0]
        d.append("\n".join(table_text("fluid", f0) for _ in range(n)))
        corpus.add("crash_fluid_blocks", cfg, "%d more [[fluid]] blocks (copies of fluid[0])" % n, d.text(),
                   expect="line", post=lambda doc, n=n, base=len(c.doc[cfg]["fluid"]): len(doc["fluid"]) == base + n)

    # Huge solid boxes.
    for cfg, lo, hi in [("dam_break", [0.0, 0.0, 0.0], [20.0, 20.0, 20.0]),
                        ("dam_break", [-1e6, -1e6, -1e6], [1e6, 1e6, 1e6]),
                        ("water_oil", [0.0, 0.0, 0.0], [20.0, 20.0, 20.0]),
                        ("two_fluids_mixed", [-1e6, -1e6, -1e6], [1e6, 1e6, 1e6]),
                        ("diffusion", [0.0, 0.0, 0.0], [20.0, 0.1, 20.0]),
                        ("diffusion", [-1e6, 0.0, -1e6], [1e6, 0.1, 1e6])]:
        d = c.edit(cfg).set("solid", "min", lo).set("solid", "max", hi)
        corpus.add("crash_huge_solid", cfg, "solid[0] box min = %s, max = %s (%g m wide)" % (tv(lo), tv(hi), hi[0] - lo[0]),
                   d.text(), expect="line", sets=[(("solid", 0, "min"), lo), (("solid", 0, "max"), hi)])
    d = c.edit("lava_lamp").append(table_text("solid", {"name": "room", "shape": "box", "min": [-10.0, -10.0, -10.0],
                                                          "max": [10.0, 10.0, 10.0]}))
    corpus.add("crash_huge_solid", "lava_lamp", "an added solid[1] 'room', box min = [-10.0, -10.0, -10.0], max = [10.0, 10.0, 10.0] (20 m)",
               d.text(), expect="line", sets=[(("solid", 1, "max"), [10.0, 10.0, 10.0])])

    # Radii of 1e3 m: emitter discs and cylinders.
    for cfg in ["pour_glass", "boiling"]:
        one(corpus, c, "crash_radius", cfg, "effects.emitter.disc", "radius", 1000.0, expect="line",
            note="a nozzle of 4e10 lattice points")
        one(corpus, c, "crash_radius", cfg, "solid", "radius", 1000.0, expect="line", note="cylinder wall of 1e3 m radius")
    for cfg, centre, vel in [("dam_break", [0.1, 0.15, 0.03], [0.0, -1.0, 0.0]), ("water_oil", [0.1, 0.25, 0.05], [0.0, -1.0, 0.0])]:
        phase = c.doc[cfg]["phase"][0]["name"]
        d = c.edit(cfg).append("[effects.emitter]\n" + table_text("effects.emitter.disc", {
            "phase": phase, "centre": centre, "radius": 1000.0, "velocity": vel}))
        corpus.add("crash_radius", cfg, "added [effects.emitter] with effects.emitter.disc[0].radius = 1000.0", d.text(),
                   expect="line", sets=[(("effects", "emitter", "disc", 0, "radius"), 1000.0)])
    one(corpus, c, "crash_radius", "pour_glass", "solid", "radius", 1e5, expect="line", note="cylinder wall of 1e5 m radius")

    # Vessel profiles of 1e5 points.
    def profile(points, n):
        hs = [p[0] for p in points]
        out = []
        for i in range(n):
            h = hs[0] + (hs[-1] - hs[0]) * i / (n - 1)
            k = min(len(points) - 2, max(0, next((j for j in range(len(hs) - 1) if hs[j + 1] >= h), len(hs) - 2)))
            t = (h - hs[k]) / (hs[k + 1] - hs[k])
            out.append([h, points[k][1] + t * (points[k + 1][1] - points[k][1])])
        return out

    lamp = c.doc["lava_lamp"]["solid"][0]["profile"]
    for cfg, n in [("lava_lamp", 100000), ("lava_lamp", 200000)]:
        prof = profile(lamp, n)
        d = c.edit(cfg).set("solid", "profile", prof)
        corpus.add("crash_profile", cfg, "solid[0].profile with %d points (heights 0..1.15 increasing)" % n, d.text(),
                   expect="line", post=lambda doc, n=n: len(doc["solid"][0]["profile"]) == n)
    for cfg in ["boiling", "dam_break"]:
        prof = profile([[0.0, 0.05], [0.14, 0.05]], 100000)
        d = c.edit(cfg).set("solid", "shape", "revolution").set("solid", "base", [0.0, 0.0, 0.0]).set("solid", "profile", prof)
        for k in ["radius", "height", "min", "max"]:
            d.delete("solid", k)
        corpus.add("crash_profile", cfg, "solid[0] made shape = \"revolution\" with a profile of 100000 points", d.text(),
                   expect="line", post=lambda doc: len(doc["solid"][0]["profile"]) == 100000)


def gen_hangs(corpus, c, rng):
    for cfg in CONFIG_NAMES:
        # The shipped scenes run on DFSPH, which has no stiffness: on WCSPH it sets the step.
        d = c.edit(cfg).set("solver", "pressure", "wcsph").set("phase", "stiffness", 1e10)
        corpus.add("hang_stiffness", cfg, "solver.pressure = \"wcsph\", phase[0].stiffness = 1e10 (c = 1e5 m/s: dt collapses)",
                   d.text(), expect="line", check="valid", sets=[(("solver", "pressure"), "wcsph"), (("phase", 0, "stiffness"), 1e10)])
    for cfg in CONFIG_NAMES:
        one(corpus, c, "hang_cfl", cfg, "solver", "cfl", 1e-12, expect="line", note="dt collapses to min_dt")
    # Not lava_lamp: its wax at 10 m^2/s steps at 7.3e-6 s (measured), 1.3e4 steps per frame,
    # inside the 1e5 bound: a slow scene, not a hang, and accepted.
    for cfg, idx in [("boiling", 0), ("boiling", 1), ("diffusion", 0)]:
        one(corpus, c, "hang_diffusivity", cfg, "phase", "thermal_diffusivity", 10.0, idx=idx, expect="line",
            note="heat_diffusion on: dt 3.6e-7 s at rest, over 1e5 steps per frame")
    one(corpus, c, "hang_diffusivity", "diffusion", "phase", "dye_diffusivity", 10.0, expect="line",
        note="dye_diffusion on: dt 3.6e-7 s at rest, over 1e5 steps per frame")


def gen_zero(corpus, c, rng):
    def others(cfg):
        return "; the other block still seeds" if len(c.doc[cfg]["fluid"]) > 1 else ""

    for cfg in ["dam_break", "lava_lamp", "water_oil", "diffusion"]:
        one(corpus, c, "zero_particles", cfg, "solver", "particle_spacing", 10.0, expect="line",
            note="larger than every block: no particle")
    for cfg in ["dam_break", "pour_glass", "boiling"]:
        one(corpus, c, "zero_particles", cfg, "solver", "particle_spacing", 0.2, expect="line",
            note="larger than fluid[0]: no particle%s" % ("; the emitter still emits later" if cfg != "dam_break" else ""))
    # wall_margin = 2 on a block whose lattice lies within 2 spacings of the container's floor.
    for cfg, mx in [("pour_glass", [0.04, 0.01, 0.04]), ("boiling", [0.05, 0.01, 0.05])]:
        d = c.edit(cfg).set("fluid", "wall_margin", 2.0).set("fluid", "max", mx)
        corpus.add("zero_particles", cfg, "fluid[0].wall_margin = 2.0 with fluid[0].max = %s: every lattice point within 2 spacings of the glass floor (the emitter still emits later)" % tv(mx),
                   d.text(), expect="line", sets=[(("fluid", 0, "wall_margin"), 2.0), (("fluid", 0, "max"), mx)])
    d = c.edit("dam_break").set("fluid", "inside", "tank").set("fluid", "wall_margin", 2.0).set("fluid", "max", [0.05715, 0.007, 0.05715])
    corpus.add("zero_particles", "dam_break", "fluid[0].inside = \"tank\", wall_margin = 2.0, max = [0.05715, 0.007, 0.05715]: one layer, 1 spacing off the floor",
               d.text(), expect="line", sets=[(("fluid", 0, "wall_margin"), 2.0)])
    for cfg, idx, lo, hi in [("dam_break", 0, [1.0, 1.0, 1.0], [1.05715, 1.1143, 1.05715]),
                             ("water_oil", 0, [2.0, 2.0, 2.0], [2.2, 2.15, 2.1]),
                             ("two_fluids_mixed", 0, [-1.0, -1.0, -1.0], [-0.8, -0.85, -0.9]),
                             ("diffusion", 1, [0.5, 0.5, 0.5], [0.6, 0.58, 0.6])]:
        d = c.edit(cfg).set("fluid", "min", lo, idx).set("fluid", "max", hi, idx)
        corpus.add("zero_particles", cfg, "fluid[%d].min = %s, max = %s: outside the domain %s..%s%s" % (
            idx, tv(lo), tv(hi), tv(c.doc[cfg]["scene"]["domain_min"]), tv(c.doc[cfg]["scene"]["domain_max"]), others(cfg)),
            d.text(), expect="line", sets=[(("fluid", idx, "min"), lo), (("fluid", idx, "max"), hi)])
    for cfg, centre in [("dam_break", [0.03, 0.05, 0.03]), ("water_oil", [0.1, 0.1, 0.05]), ("diffusion", [0.05, 0.04, 0.05])]:
        d = c.edit(cfg).set("fluid", "shape", "sphere").set("fluid", "centre", centre).set("fluid", "radius", 1e-6)
        d.delete("fluid", "min").delete("fluid", "max")
        corpus.add("zero_particles", cfg, "fluid[0] shape = \"sphere\", centre = %s, radius = 1e-06%s" % (tv(centre), others(cfg)), d.text(),
                   expect="line", sets=[(("fluid", 0, "radius"), 1e-6)])
    for cfg, lo, hi in [("dam_break", [0.01, 0.01, 0.01], [0.012, 0.012, 0.012]),
                        ("water_oil", [0.05, 0.05, 0.05], [0.055, 0.055, 0.055]),
                        ("lava_lamp", [-0.01, 0.1, -0.01], [0.01, 0.12, 0.01])]:
        d = c.edit(cfg).set("fluid", "min", lo).set("fluid", "max", hi)
        corpus.add("zero_particles", cfg, "fluid[0].min = %s, max = %s: smaller than a spacing (%g m)%s" % (
            tv(lo), tv(hi), c.doc[cfg]["solver"]["particle_spacing"], others(cfg)), d.text(), expect="line",
            sets=[(("fluid", 0, "max"), hi)])


def gen_other_measured(corpus, c, rng):
    # inf in a vessel profile
    lamp = [list(p) for p in c.doc["lava_lamp"]["solid"][0]["profile"]]
    inf = float("inf")
    for k, (i, j, v) in enumerate([(1, 1, inf), (3, 1, inf), (3, 0, inf), (0, 0, -inf), (1, 1, float("nan"))]):
        prof = [list(p) for p in lamp]
        prof[i][j] = v
        d = c.edit("lava_lamp").set("solid", "profile", prof)
        corpus.add("profile_inf", "lava_lamp", "solid[0].profile point %d %s = %s" % (i, "radius" if j else "height", tv(v)),
                   d.text(), expect="key:solid[0].profile", post=lambda doc, i=i, j=j, v=v: same(doc["solid"][0]["profile"][i][j], v))
    prof = [[0.0, 0.05], [0.07, inf], [0.14, 0.05]]
    d = c.edit("boiling").set("solid", "shape", "revolution").set("solid", "profile", prof).delete("solid", "radius").delete("solid", "height")
    corpus.add("profile_inf", "boiling", "solid[0] made a revolution, profile = [[0.0, 0.05], [0.07, inf], [0.14, 0.05]]", d.text(),
               expect="key:solid[0].profile", post=lambda doc: math.isinf(doc["solid"][0]["profile"][1][1]))

    # heat (and dye) sources with min > max
    src = c.doc["lava_lamp"]["effects"]["heat_diffusion"]["source"]
    d = c.edit("lava_lamp").set("effects.heat_diffusion.source", "min", src[0]["max"]).set("effects.heat_diffusion.source", "max", src[0]["min"])
    corpus.add("source_inverted", "lava_lamp", "effects.heat_diffusion.source[0] min = %s, max = %s (swapped)" % (tv(src[0]["max"]), tv(src[0]["min"])),
               d.text(), expect="key:effects.heat_diffusion.source[0]", sets=[(("effects", "heat_diffusion", "source", 0, "min"), src[0]["max"])])
    d = c.edit("lava_lamp").set("effects.heat_diffusion.source", "max", [0.3, 0.7, 0.3], 1)
    corpus.add("source_inverted", "lava_lamp", "effects.heat_diffusion.source[1].max = [0.3, 0.7, 0.3] below its min y 0.8",
               d.text(), expect="key:effects.heat_diffusion.source[1]", sets=[(("effects", "heat_diffusion", "source", 1, "max"), [0.3, 0.7, 0.3])])
    d = c.edit("lava_lamp").set("effects.heat_diffusion.source", "max", [-0.3, 0.08, 0.3])
    corpus.add("source_inverted", "lava_lamp", "effects.heat_diffusion.source[0].max = [-0.3, 0.08, 0.3]: max x = min x (empty box)",
               d.text(), expect="key:effects.heat_diffusion.source[0]", sets=[(("effects", "heat_diffusion", "source", 0, "max"), [-0.3, 0.08, 0.3])])
    for cfg, eff, vkey, val in [("diffusion", "heat_diffusion", "temperature", 90.0), ("boiling", "heat_diffusion", "temperature", 150.0),
                                ("diffusion", "dye_diffusion", "concentration", 1.0)]:
        lo, hi = [0.2, 0.1, 0.1], [0.0, 0.0, 0.0]
        k = len(c.doc[cfg].get("effects", {}).get(eff, {}).get("source", []))  # appended after the scene's own
        d = c.edit(cfg).append(table_text("effects.%s.source" % eff, {"min": lo, "max": hi, vkey: val, "rate": 1.0}))
        corpus.add("source_inverted", cfg, "added effects.%s.source[%d] min = %s, max = %s" % (eff, k, tv(lo), tv(hi)), d.text(),
                   expect="key:effects.%s.source[%d]" % (eff, k), sets=[(("effects", eff, "source", k, "max"), hi)])

    # fractions that are all zero
    for cfg, fr in [("two_fluids_mixed", [0, 0]), ("water_oil", [0.0, 0.0])]:
        one(corpus, c, "fractions_zero", cfg, "fluid", "fractions", fr, expect="key:fluid[0].fractions")
    for cfg, idx, phases, fr in [("lava_lamp", 1, ["fluid", "wax"], [0, 0]), ("boiling", 0, ["water", "vapour"], [0, 0]),
                                 ("diffusion", 0, ["liquid"], [0])]:
        d = c.edit(cfg).delete("fluid", "phase", idx).set("fluid", "phases", phases, idx).set("fluid", "fractions", fr, idx)
        corpus.add("fractions_zero", cfg, "fluid[%d] phases = %s, fractions = %s" % (idx, tv(phases), tv(fr)), d.text(),
                   expect="key:fluid[%d].fractions" % idx, sets=[(("fluid", idx, "fractions"), fr)])

    # a block inside an open glass that reaches above its rim
    for cfg, y in [("pour_glass", 0.2), ("pour_glass", 0.13), ("boiling", 0.2), ("boiling", 0.5)]:
        mx = list(c.doc[cfg]["fluid"][0]["max"])
        mx[1] = y
        g = c.doc[cfg]["solid"][0]
        d = c.edit(cfg).set("fluid", "max", mx)
        corpus.add("inside_above_rim", cfg, "fluid[0] inside = \"glass\", max = %s above the rim at y = %g" % (tv(mx), g["base"][1] + g["height"]),
                   d.text(), expect="key:fluid[0]", sets=[(("fluid", 0, "max"), mx)])
    d = c.edit("dam_break").set("solid", "open_top", True).set("fluid", "inside", "tank").set("fluid", "max", [0.05715, 0.25, 0.05715])
    corpus.add("inside_above_rim", "dam_break", "solid[0] open_top = true; fluid[0] inside = \"tank\", max = [0.05715, 0.25, 0.05715] above the tank's top y = 0.17145",
               d.text(), expect="key:fluid[0]", sets=[(("fluid", 0, "max"), [0.05715, 0.25, 0.05715])])


BAD_NAMES = [
    ("quote", "it's"),
    ("double quote", 'say "hi"'),
    ("command substitution", "$(touch /tmp/mf_pwned)"),
    ("semicolon", "a; rm -rf mf_x"),
    ("backticks", "`id`"),
    ("slash", "a/b"),
    ("dot-dot", ".."),
    ("dot-dot path", "../../escape"),
    ("absolute path", "/tmp/mf_absolute"),
    ("comma", "water,oil"),
    ("empty", ""),
    ("NUL byte", "wa\u0000ter"),
    ("newline", "two\nlines"),
    ("very long", "n" * 10000),
]


def rename_phase(d, old, new):
    """Renames a phase everywhere: its name, every "old" string value and [render.material.old]."""
    q_old, q_new = tstr(old), tstr(new)
    for i, line in enumerate(d.lines):
        cp = code_part(line)
        m = HEADER.match(cp)
        if m and m.group(2).replace(" ", "") == "render.material." + old:
            d.lines[i] = "[render.material.%s]" % q_new
            continue
        if q_old in cp:
            d.lines[i] = cp.replace(q_old, q_new) + line[len(cp):]
    return d


def gen_names(corpus, c, rng):
    cfgs = ["dam_break", "lava_lamp", "water_oil", "pour_glass", "boiling", "two_fluids_mixed", "diffusion"]
    for k, (what, name) in enumerate(BAD_NAMES):
        cfg = cfgs[k % len(cfgs)]
        one(corpus, c, "bad_scene_name", cfg, "scene", "name", name, note=what)
    for k, (what, name) in enumerate(BAD_NAMES):
        cfg = cfgs[(k + 3) % len(cfgs)]
        pidx = 0
        old = c.doc[cfg]["phase"][pidx]["name"]
        d = rename_phase(c.edit(cfg), old, name)

        def post(doc, old=old, name=name):
            if doc["phase"][0]["name"] != name:
                return False
            mats = doc.get("render", {}).get("material", {})
            return old not in mats and old not in list(strings_in(doc))

        corpus.add("bad_phase_name", cfg, "phase[0].name = %s (%s; was \"%s\", every reference renamed)" % (short(name), what, old),
                   d.text(), expect="key:phase[0].name", post=post)


# --------------------------------------------------------------------------------------------
# Generic classes


def gen_syntax(corpus, c, rng):
    cases = [
        ("dam_break", "header", "solver", 0, "[solver", "unclosed table header '[solver'"),
        ("lava_lamp", "header", "phase", 1, "[[phase]", "array-of-tables header '[[phase]' unclosed"),
        ("water_oil", "header", "scene", 0, "[scene]]", "header '[scene]]'"),
        ("pour_glass", "header", "fluid", 0, "[[ fluid ]", "header '[[ fluid ]' mismatched brackets"),
        ("diffusion", "header", "effects.gravity", 0, "[]", "empty header '[]'"),
        ("boiling", "header", "effects.phase_change", 0, "[effects..phase_change]", "header with an empty key part"),
        ("dam_break", "key", "solver", "cfl", "cfl =", "key with no value 'cfl ='"),
        ("two_fluids_mixed", "key", "solver", "cfl", "cfl 0.4", "missing '=' 'cfl 0.4'"),
        ("lava_lamp", "key", "scene", "name", 'name = "lava_lamp', "unterminated string"),
        ("boiling", "key", "scene", "domain_min", "domain_min = [-0.1, -0.08", "unterminated array"),
        ("water_oil", "key", "scene", "name", 'name = "water\\qoil"', "invalid escape \\q"),
        ("pour_glass", "key", "solver", "cfl", "cfl = 0.4.1", "number 0.4.1"),
        ("diffusion", "key", "solver", "cfl", "cfl = 1e", "number 1e"),
        ("dam_break", "key", "solver", "cfl", "cfl = .5", "number .5"),
        ("lava_lamp", "key", "scene", "frame_rate", "frame_rate = 010", "integer with a leading zero 010"),
        ("two_fluids_mixed", "key", "solver", "cfl", "cfl = 0.4 0.5", "two values 'cfl = 0.4 0.5'"),
        ("dam_break", "key", "fluid", "phase", 'phase = "water"\nvelocity = {x = 1.0', "unterminated inline table"),
        ("water_oil", "key", "solver", "cfl", "cf l = 0.4", "space in a bare key"),
        ("boiling", "key", "solver", "cfl", "= 0.4", "no key '= 0.4'"),
        ("pour_glass", "key", "scene", "end_time", "end_time = 2024-13-45", "invalid date 2024-13-45"),
        ("diffusion", "key", "scene", "name", 'name = "diff\x01usion"', "raw control character U+0001 in a string"),
        ("lava_lamp", "key", "solver", "cfl", "cfl = 0.4 # comment \x07 with a bell", "raw control character U+0007 in a comment"),
        ("dam_break", "key", "scene", "end_time", "]", "stray ']' line"),
        ("two_fluids_mixed", "key", "scene", "name", 'name = """two_fluids', 'unterminated multi-line string """'),
        ("water_oil", "key", "solver", "cfl", "cfl = +-1", "number +-1"),
        ("pour_glass", "key", "solver", "cfl", "cfl = 1__0", "number 1__0"),
        ("boiling", "key", "solver", "cfl", "cfl = 0x1.8p1", "hexadecimal float 0x1.8p1"),
        ("diffusion", "key", "scene", "name", "name = 'diffusion", "unterminated literal string"),
        ("lava_lamp", "key", "scene", "name", "scene. = 1", "key with a trailing dot"),
        ("dam_break", "key", "scene", "name", "true", "bare value 'true' on a line"),
        ("water_oil", "key", "scene", "name", 'name = "\\uD800"', "escape of a surrogate \\uD800"),
        ("two_fluids_mixed", "key", "scene", "name", 'name = "\\U00110000"', "escape beyond U+10FFFF"),
        ("pour_glass", "key", "solver", "cfl", "cfl = 0.4,", "trailing comma after a value"),
        ("boiling", "key", "phase", "name", 'name = "water" = "x"', "two '=' on a line"),
        ("diffusion", "key", "solver", "max_dt", "max_dt = 4e-3e2", "number 4e-3e2"),
        ("lava_lamp", "key", "solver", "cfl", "cfl = inf0", "number inf0"),
        ("dam_break", "key", "render", "width", "width = 480_", "trailing underscore 480_"),
        ("water_oil", "key", "fluid", "fractions", "fractions = [0.5,, 0.5]", "array with an empty element"),
    ]
    for cfg, kind, sec, what, text, desc in cases:
        d = c.edit(cfg)
        if kind == "header":
            d.replace_header(sec, text, what)
        else:
            d.replace_key_line(sec, what, text)
        shown = text.replace("\n", "\\n").replace("\x01", "\\x01").replace("\x07", "\\x07")
        corpus.add("syntax", cfg, "%s: %s" % (desc, shown), d.text(), expect="line", check="invalid")
    # Bare carriage returns as line ends; invalid UTF-8 in a comment and in a string.
    t = c.text["dam_break"].replace("\n", "\r", 12).encode()
    corpus.add("syntax", "dam_break", "the first 12 line ends are bare CR (not allowed)", t, check="invalid")
    t = c.text["lava_lamp"].encode().replace(b"# The vessel:", b"# The v\xc3\x28essel:", 1)
    corpus.add("syntax", "lava_lamp", "invalid UTF-8 (C3 28) in a comment", t, check="invalid")
    t = c.text["two_fluids_mixed"].encode().replace(b'name = "light"', b'name = "li\xffght"', 1)
    corpus.add("syntax", "two_fluids_mixed", "invalid UTF-8 (FF) in phase[0].name", t, check="invalid")


def truncated_check(cfg_doc):
    """Not valid TOML, or valid but the first [[fluid]] lacks a required key (or is absent)."""

    def check(data):
        try:
            doc = tomllib.loads(data.decode("utf-8"))
        except (tomllib.TOMLDecodeError, UnicodeDecodeError):
            return True
        f = doc.get("fluid")
        if not f:
            return True
        f0 = f[0]
        req = ["centre", "radius"] if f0.get("shape") == "sphere" else ["min", "max"]
        req.append("phases" if "phases" in cfg_doc["fluid"][0] else "phase")
        return any(k not in f0 for k in req)

    return check


def value_span(line_text, offset_of_line):
    """Offsets (open, close) of a key line's value when it is a string or an array."""
    eq = line_text.index("=")
    i = eq + 1
    while line_text[i] in " \t":
        i += 1
    if line_text[i] == '"':
        j = i + 1
        while line_text[j] != '"':
            j += 2 if line_text[j] == "\\" else 1
        return offset_of_line + i, offset_of_line + j
    if line_text[i] == "[":
        depth = 0
        j = i
        while True:
            if line_text[j] == "[":
                depth += 1
            elif line_text[j] == "]":
                depth -= 1
                if depth == 0:
                    break
            j += 1
        return offset_of_line + i, offset_of_line + j
    return None


def gen_truncations(corpus, c, rng):
    for cfg in CONFIG_NAMES:
        text = c.text[cfg]
        d = c.edit(cfg)
        offsets = [0]
        for line in d.lines:
            offsets.append(offsets[-1] + len(line) + 1)
        s, e = d.section("fluid", 0)
        f0 = c.doc[cfg]["fluid"][0]
        keys = ["min", "max", "phases" if "phases" in f0 else "phase"]
        last = max(d.key_line("fluid", k) for k in keys)
        lkey = [k for k in keys if d.key_line("fluid", k) == last][0]
        span = value_span(d.lines[last], offsets[last])
        assert span, (cfg, lkey)
        close = span[1]  # the value's closing '"' or ']': the cut keeps text[:cut], cut <= close
        assert text[close] in '"]'
        cuts = sorted(set([rng.randrange(1, close + 1) for _ in range(3)] +
                          [rng.randrange(offsets[s], close + 1) for _ in range(3)]))
        for cut in cuts:
            line_no = text.count("\n", 0, cut) + 1
            where = "inside fluid[0]" if cut > offsets[s] else "before fluid[0]"
            corpus.add("truncation", cfg, "cut after %d of %d bytes (line %d, %s; its last required key '%s' ends at byte %d)"
                       % (cut, len(text.encode()), line_no, where, lkey, close + 1), text[:cut].encode(),
                       check=truncated_check(c.doc[cfg]))
        # Inside a string or an array value anywhere (not in a comment).
        spans = []
        for i, line in enumerate(d.lines):
            cp = code_part(line)
            if "=" in cp and not HEADER.match(cp):
                sp = value_span(cp, offsets[i])
                if sp and sp[1] - sp[0] >= 2:
                    spans.append((i, cp.split("=")[0].strip(), sp))
        for i, key, (a, b) in rng.sample(spans, 2):
            cut = rng.randrange(a + 1, b)
            corpus.add("truncation", cfg, "cut after %d of %d bytes, inside the value of '%s' (line %d)" % (cut, len(text.encode()), key, i + 1),
                       text[:cut].encode(), check="invalid")


def gen_wrong_types(corpus, c, rng):
    R = Raw
    cases = [
        ("dam_break", "solver", "particle_spacing", "0.00357", "a string for a number"),
        ("lava_lamp", "solver", "cfl", True, "a boolean for a number"),
        ("water_oil", "scene", "end_time", [8.0], "an array for a number"),
        ("pour_glass", "scene", "domain_min", 0.0, "a number for a vector"),
        ("boiling", "scene", "domain_max", [0.1, 0.2], "2 components for a vector"),
        ("diffusion", "scene", "domain_max", ["0.21", "0.11", "0.11"], "strings in a vector"),
        ("two_fluids_mixed", "scene", "frame_rate", R("1979-05-27"), "a date for a number"),
        ("dam_break", "scene", "name", 42, "a number for a name"),
        ("water_oil", "phase", "rest_density", R("{ value = 1000.0 }"), "an inline table for a number"),
        ("pour_glass", "solid", "open_top", "yes", "a string for a boolean"),
        ("boiling", "solid", "open_top", 1, "a number for a boolean"),
        ("diffusion", "solid", "shape", 3, "a number for a shape"),
        ("lava_lamp", "fluid", "min", "-0.2, 0.0, -0.2", "a string for a vector"),
        ("dam_break", "fluid", "phase", 1, "a number for a phase name"),
        ("two_fluids_mixed", "fluid", "phases", "light", "a string for an array of phase names"),
        ("water_oil", "fluid", "fractions", 0.5, "a number for an array of fractions"),
        ("lava_lamp", "fluid", "jitter", "0.2", "a string for a number"),
        ("diffusion", "effects.viscosity", "stability_factor", [0.1], "an array for a number"),
        ("dam_break", "effects.gravity", "acceleration", -9.81, "a number for a vector"),
        ("pour_glass", "effects.viscosity", "wall_friction", "1", "a string for a number"),
        ("water_oil", "solver", "density_formulation", 1, "a number for a choice"),
        ("boiling", "solver", "kernel", True, "a boolean for a choice"),
        ("lava_lamp", "render", "width", "216", "a string for a number"),
        ("lava_lamp", "render", "floor", "false", "a string for a boolean"),
        ("dam_break", "render.material.tank", "thickness", [0.003], "an array for a number"),
        ("lava_lamp", "surfacing", "phases", "wax", "a string for an array of phase names"),
        ("two_fluids_mixed", "solver", "free_surface_completion", 0, "a number for a boolean"),
        ("boiling", "effects.phase_change", "liquid", ["water"], "an array for a phase name"),
        ("pour_glass", "effects.emitter.disc", "velocity", R("{ x = 0.0, y = -1.5, z = 0.0 }"), "an inline table for a vector"),
        ("lava_lamp", "effects.heat_diffusion.source", "temperature", "75", "a string for a number"),
        ("water_oil", "effects.interface_tension", "sigma", R("1979-05-27T07:32:00Z"), "a date-time for a number"),
        # Fractional values for keys that are counts.
        ("dam_break", "render", "width", 480.5, "a fraction for a count (pixels)"),
        ("two_fluids_mixed", "solver", "reorder_interval", 10.5, "a fraction for a count (steps)"),
        ("water_oil", "solver", "max_retries", 2.5, "a fraction for a count (retries)"),
        ("lava_lamp", "render", "samples", 16.9, "a fraction for a count (samples)"),
        ("boiling", "effects.phase_change", "sites", 4.5, "a fraction for a count (sites)"),
    ]
    for cfg, sec, key, value, note in cases:
        one(corpus, c, "wrong_type", cfg, sec, key, value, note=note)
    # Tables of the wrong kind.
    d = c.edit("dam_break").replace_header("phase", "[phase]")
    corpus.add("wrong_type", "dam_break", "[phase] (a table) instead of [[phase]]", d.text(), expect="key:phase",
               post=lambda doc: isinstance(doc["phase"], dict))
    d = c.edit("water_oil").replace_header("fluid", "[fluid]")
    corpus.add("wrong_type", "water_oil", "[fluid] (a table) instead of [[fluid]]", d.text(), expect="key:fluid",
               post=lambda doc: isinstance(doc["fluid"], dict))
    d = c.edit("pour_glass").replace_header("scene", "[[scene]]")
    corpus.add("wrong_type", "pour_glass", "[[scene]] (an array of tables) instead of [scene]", d.text(), expect="key:scene",
               post=lambda doc: isinstance(doc["scene"], list))
    d = c.edit("diffusion").replace_header("solid", "[solid]")
    corpus.add("wrong_type", "diffusion", "[solid] (a table) instead of [[solid]]", d.text(), expect="key:solid",
               post=lambda doc: isinstance(doc["solid"], dict))
    d = c.edit("lava_lamp").set("solid", "profile", [[0.0, "0.13"], [0.35, 0.17], [0.8, 0.15], [1.15, 0.1]])
    corpus.add("wrong_type", "lava_lamp", "solid[0].profile = [[0.0, \"0.13\"], ...] (a string radius)", d.text(),
               expect="key:solid[0].profile", post=lambda doc: doc["solid"][0]["profile"][0][1] == "0.13")
    d = c.edit("lava_lamp").set("solid", "profile", [0.0, 0.13, 0.35, 0.17])
    corpus.add("wrong_type", "lava_lamp", "solid[0].profile = [0.0, 0.13, 0.35, 0.17] (flat, not points)", d.text(),
               expect="key:solid[0].profile", post=lambda doc: doc["solid"][0]["profile"][0] == 0.0)
    d = c.edit("dam_break").replace_header("effects.gravity", "[[effects.gravity]]")
    corpus.add("wrong_type", "dam_break", "[[effects.gravity]] (an array of tables) instead of [effects.gravity]", d.text(),
               expect="key:effects.gravity", post=lambda doc: isinstance(doc["effects"]["gravity"], list))


def gen_unknown_keys(corpus, c, rng):
    cases = [
        ("dam_break", "scene", "end_tme = 0.6", "scene.end_tme"),
        ("lava_lamp", "solver", "partcle_spacing = 0.0229", "solver.partcle_spacing"),
        ("water_oil", "solver", "cfl_number = 0.4", "solver.cfl_number"),
        ("pour_glass", "phase", "viscocity = 0.2", "phase[0].viscocity"),
        ("boiling", "solid", "radious = 0.05", "solid[0].radious"),
        ("diffusion", "fluid", "temprature = 80.0", "fluid[0].temprature"),
        ("two_fluids_mixed", "effects.gravity", "accel = [0.0, -9.81, 0.0]", "effects.gravity.accel"),
        ("lava_lamp", "effects.pressure", "wall_scal = 1.0", "effects.pressure.wall_scal"),
        ("dam_break", "render", "resolution = 3", "render.resolution"),
        ("lava_lamp", "render.material.wax", "colour_x = [1.0, 1.0, 1.0]", "render.material.wax.colour_x"),
        ("lava_lamp", "surfacing", "voxel_size = 0.01", "surfacing.voxel_size"),
        ("lava_lamp", "effects.heat_diffusion.source", "temp = 75.0", "effects.heat_diffusion.source[0].temp"),
        ("pour_glass", "effects.emitter.disc", "speed = 1.5", "effects.emitter.disc[0].speed"),
        ("boiling", "effects.buoyancy.gas", "coef = 1.0", "effects.buoyancy.gas[0].coef"),
        ("boiling", "effects.phase_change", "sites_count = 5", "effects.phase_change.sites_count"),
        ("pour_glass", "effects.trapped_air", "max_bubbles = 400", "effects.trapped_air.max_bubbles"),
        ("water_oil", "effects.interface_tension", "sigm = 0.6", "effects.interface_tension.sigm"),
        ("diffusion", "", "version = 1", "version"),
        ("two_fluids_mixed", "scene", '"näme" = "x"', "scene.näme"),
        ("water_oil", "scene", '"" = 1', "scene."),
        ("dam_break", "scene", "domain.min = [0.0, 0.0, 0.0]", "scene.domain"),
    ]
    for cfg, sec, line, key in cases:
        d = c.edit(cfg).add_line(sec, line)
        corpus.add("unknown_key", cfg, "%s: '%s'" % ("top level" if not sec else "[%s]" % sec, line), d.text(),
                   expect="key:" + key, check="valid")
    d = c.edit("diffusion").append("[solvr]\ncfl = 0.4")
    corpus.add("unknown_key", "diffusion", "unknown table [solvr] (cfl = 0.4)", d.text(), expect="key:solvr")
    d = c.edit("dam_break").append("[effects.gravty]\nacceleration = [0.0, -9.81, 0.0]")
    corpus.add("unknown_key", "dam_break", "unknown effect [effects.gravty]", d.text(), expect="key:effects.gravty")
    d = c.edit("pour_glass").append("[render.materials.glass]\nthickness = 0.002")
    corpus.add("unknown_key", "pour_glass", "unknown table [render.materials.glass]", d.text(), expect="key:render.materials")
    d = c.edit("boiling").append("[render.material.glas]\nthickness = 0.002")
    corpus.add("unknown_key", "boiling", "[render.material.glas]: names no phase or solid", d.text(), expect="key:render.material.glas")
    # Deep nesting.
    d = c.edit("water_oil").add_line("", "deep = " + "[" * 300 + "]" * 300)
    corpus.add("unknown_key", "water_oil", "top-level deep = [[[...]]] nested 300 deep", d.text(), expect="line", check="none")
    d = c.edit("lava_lamp").append("[" + ".".join(["a"] * 10000) + "]\nx = 1")
    corpus.add("unknown_key", "lava_lamp", "unknown table [a.a.a...] 10000 levels deep", d.text(), expect="line", check="none")
    d = c.edit("two_fluids_mixed").add_line("", ".".join(["b"] * 10000) + " = 1")
    corpus.add("unknown_key", "two_fluids_mixed", "unknown dotted key b.b.b... = 1, 10000 levels deep", d.text(), expect="line", check="none")
    d = c.edit("dam_break").append("[" + ".".join(["a"] * 50000) + "]\nx = 1")
    corpus.add("unknown_key", "dam_break", "unknown table [a.a.a...] 50000 levels deep (100 KB)", d.text(), expect="line", check="none")
    d = c.edit("water_oil").add_line("", ".".join(["b"] * 50000) + " = 1")
    corpus.add("unknown_key", "water_oil", "unknown dotted key b.b.b... = 1, 50000 levels deep (100 KB)", d.text(), expect="line", check="none")
    d = c.edit("dam_break").add_line("", "deep = " + "{a = " * 2000 + "1" + "}" * 2000)
    corpus.add("unknown_key", "dam_break", "top-level deep = {a = {a = ...}} nested 2000 deep", d.text(), expect="line", check="none")


def gen_duplicates(corpus, c, rng):
    toml_dups = [
        ("dam_break", "solver", "cfl = 0.3", "solver.cfl given twice"),
        ("lava_lamp", "scene", 'name = "other"', "scene.name given twice"),
        ("water_oil", "phase", 'name = "brine"', "phase[0].name given twice"),
        ("pour_glass", "fluid", "min = [-0.03, 0.0, -0.03]", "fluid[0].min given twice"),
        ("boiling", "effects.phase_change", "sites = 4", "effects.phase_change.sites given twice"),
        ("diffusion", "solver", "\"cfl\" = 0.3", "solver.cfl given twice (once quoted)"),
        ("two_fluids_mixed", "solver", "cfl = \"0.4\"", "solver.cfl given twice with different types"),
        ("lava_lamp", "effects.heat_diffusion.source", "rate = 2.0", "effects.heat_diffusion.source[0].rate given twice"),
    ]
    for cfg, sec, line, desc in toml_dups:
        d = c.edit(cfg).add_line(sec, line)
        corpus.add("duplicate_key", cfg, "%s ('%s')" % (desc, line), d.text(), check="invalid")
    tables = [
        ("dam_break", '[scene]\nname = "again"', "[scene] twice"),
        ("water_oil", "[solver]\ncfl = 0.3", "[solver] twice"),
        ("two_fluids_mixed", "[effects.gravity]", "[effects.gravity] twice"),
        ("dam_break", "[render.material.tank]\nthickness = 0.002", "[render.material.tank] twice"),
        ("lava_lamp", "[effects.heat_diffusion]", "[effects.heat_diffusion] twice"),
        ("pour_glass", '[phase]\nname = "x"', "[phase] after [[phase]]"),
        ("diffusion", "[render]\nwidth = 100\n[render]\nheight = 100", "[render] twice"),
    ]
    for cfg, block, desc in tables:
        d = c.edit(cfg).append(block)
        corpus.add("duplicate_key", cfg, desc, d.text(), check="invalid")
    d = c.edit("boiling").add_line("", "solver.cfl = 0.3")
    corpus.add("duplicate_key", "boiling", "top-level dotted solver.cfl = 0.3 and a [solver] table", d.text(), check="invalid")
    d = c.edit("water_oil").add_line("", "scene = 1")
    corpus.add("duplicate_key", "water_oil", "top-level scene = 1 and a [scene] table", d.text(), check="invalid")
    d = c.edit("lava_lamp").add_line("render", "material = 1")
    corpus.add("duplicate_key", "lava_lamp", "render.material = 1 and [render.material.*] tables", d.text(), check="invalid")
    # Duplicates the scene reader has to find.
    for cfg in ["dam_break", "water_oil"]:
        p = dict(c.doc[cfg]["phase"][0])
        d = c.edit(cfg).append(table_text("phase", p))
        n = len(c.doc[cfg]["phase"])
        corpus.add("duplicate_key", cfg, "phase[%d] a copy of phase[0], the same name \"%s\"" % (n, p["name"]), d.text(),
                   expect="key:phase[%d].name" % n, post=lambda doc, n=n, p=p: doc["phase"][n]["name"] == p["name"])
    for cfg in ["pour_glass", "two_fluids_mixed", "lava_lamp"]:
        s = dict(c.doc[cfg]["solid"][0])
        d = c.edit(cfg).append(table_text("solid", s))
        n = len(c.doc[cfg]["solid"])
        corpus.add("duplicate_key", cfg, "solid[%d] a copy of solid[0], the same name \"%s\"" % (n, s["name"]), d.text(),
                   expect="key:solid[%d].name" % n, post=lambda doc, n=n, s=s: doc["solid"][n]["name"] == s["name"])
    one(corpus, c, "duplicate_key", "lava_lamp", "surfacing", "phases", ["wax", "wax", "fluid"], note="a phase listed twice")
    one(corpus, c, "duplicate_key", "two_fluids_mixed", "fluid", "phases", ["light", "light"], note="a phase listed twice")


def gen_numbers(corpus, c, rng):
    big = [
        ("dam_break", "solver", "particle_spacing", 1e300),
        ("lava_lamp", "scene", "end_time", 1e300),
        ("water_oil", "scene", "frame_rate", 1e300),
        ("pour_glass", "scene", "domain_max", [1e300, 0.25, 0.1]),
        ("boiling", "phase", "rest_density", 1e300),
        ("diffusion", "phase", "stiffness", 1e300),
        ("two_fluids_mixed", "phase", "viscosity", 1e300),
        ("dam_break", "fluid", "velocity", [0.0, -1e300, 0.0]),
        ("lava_lamp", "fluid", "temperature", 1e300),
        ("water_oil", "fluid", "seed", 1e300),
        ("dam_break", "render", "width", 1e300),
        ("boiling", "effects.gravity", "acceleration", [0.0, -1e300, 0.0]),
        ("pour_glass", "effects.emitter.disc", "end", 1e300),
        ("boiling", "solid", "radius", 1e300),
        ("diffusion", "solid", "max", [1e300, 0.1, 0.1]),
        ("two_fluids_mixed", "fluid", "min", [-1e300, 0.0, 0.0]),
        ("lava_lamp", "effects.heat_diffusion.source", "rate", 1.7976931348623157e308),
        ("dam_break", "solver", "max_dt", -1e300),
        ("water_oil", "fluid", "seed", 9223372036854775807),
        ("lava_lamp", "effects.interface_tension", "sigma", 1e300),
    ]
    for cfg, sec, key, v in big:
        one(corpus, c, "huge_number", cfg, sec, key, v)
    for cfg, sec, key, raw, note in [("diffusion", "solver", "cfl", "1e309", "overflows a double"),
                                     ("two_fluids_mixed", "fluid", "seed", "99999999999999999999", "overflows a 64-bit integer"),
                                     ("boiling", "scene", "end_time", "-1e309", "overflows a double")]:
        one(corpus, c, "huge_number", cfg, sec, key, Raw(raw), note=note, expect="line", check="none")
    # A vessel profile point at 1e300 m (the profile has no range today).
    prof = [list(p) for p in c.doc["lava_lamp"]["solid"][0]["profile"]]
    prof[-1][0] = 1e300
    d = c.edit("lava_lamp").set("solid", "profile", prof)
    corpus.add("huge_number", "lava_lamp", "solid[0].profile last point height = 1e+300", d.text(), expect="key:solid[0].profile",
               post=lambda doc: doc["solid"][0]["profile"][-1][0] == 1e300)
    prof = [list(p) for p in c.doc["lava_lamp"]["solid"][0]["profile"]]
    prof[1][1] = 1e300
    d = c.edit("lava_lamp").set("solid", "profile", prof)
    corpus.add("huge_number", "lava_lamp", "solid[0].profile point 1 radius = 1e+300", d.text(), expect="key:solid[0].profile",
               post=lambda doc: doc["solid"][0]["profile"][1][1] == 1e300)

    nan, inf = float("nan"), float("inf")
    nans = [
        ("dam_break", "solver", "particle_spacing", nan),
        ("lava_lamp", "solver", "cfl", inf),
        ("water_oil", "scene", "end_time", -inf),
        ("pour_glass", "scene", "domain_min", [nan, 0.0, 0.0]),
        ("boiling", "scene", "domain_max", [0.1, inf, 0.1]),
        ("diffusion", "phase", "rest_density", nan),
        ("two_fluids_mixed", "phase", "stiffness", inf),
        ("dam_break", "phase", "viscosity", nan),
        ("lava_lamp", "phase", "thermal_expansion", nan),
        ("water_oil", "phase", "interface_colour", -inf),
        ("pour_glass", "fluid", "min", [-0.04, nan, -0.04]),
        ("boiling", "fluid", "temperature", inf),
        ("diffusion", "fluid", "dye", nan),
        ("two_fluids_mixed", "fluid", "fractions", [nan, 0.5]),
        ("lava_lamp", "fluid", "jitter", nan),
        ("dam_break", "effects.gravity", "acceleration", [0.0, nan, 0.0]),
        ("pour_glass", "effects.emitter.disc", "velocity", [0.0, -inf, 0.0]),
        ("boiling", "effects.phase_change", "boiling_temperature", nan),
        ("lava_lamp", "effects.heat_diffusion.source", "temperature", inf),
        ("water_oil", "effects.pressure", "reference_level", nan),
        ("dam_break", "render", "camera_position", [nan, 0.24, 0.42]),
        ("lava_lamp", "render", "fov", inf),
        ("boiling", "solid", "radius", nan),
        ("diffusion", "solver", "max_dt", inf),
        ("pour_glass", "effects.trapped_air", "max_air", nan),
    ]
    for cfg, sec, key, v in nans:
        one(corpus, c, "nan_inf", cfg, sec, key, v)
    for cfg, sec, key, raw in [("two_fluids_mixed", "solver", "cfl", "+nan"), ("water_oil", "solver", "cfl", "-nan"),
                               ("dam_break", "scene", "frame_rate", "+inf")]:
        one(corpus, c, "nan_inf", cfg, sec, key, Raw(raw))

    oor = [
        ("dam_break", "solver", "particle_spacing", 0.0),
        ("lava_lamp", "solver", "particle_spacing", -0.0229),
        ("water_oil", "solver", "particle_spacing", 11.0),
        ("pour_glass", "solver", "smoothing_ratio", 1.0),
        ("boiling", "solver", "smoothing_ratio", 5.0),
        ("diffusion", "solver", "cfl", 0.0),
        ("two_fluids_mixed", "solver", "cfl", 30.0),
        ("dam_break", "solver", "force_factor", 0.0),
        ("lava_lamp", "solver", "max_dt", 2.0),
        ("water_oil", "solver", "min_dt", 0.01),
        ("pour_glass", "solver", "boundary_spacing_ratio", 0.1),
        ("boiling", "solver", "reorder_interval", 0),
        ("diffusion", "solver", "max_retries", 41),
        ("two_fluids_mixed", "phase", "rest_density", 0.0),
        ("dam_break", "phase", "rest_density", -1000.0),
        ("lava_lamp", "phase", "stiffness", 0.0),
        ("water_oil", "phase", "stiffness", -200.0),
        ("pour_glass", "phase", "viscosity", -0.2),
        ("boiling", "phase", "thermal_diffusivity", -2e-3),
        ("lava_lamp", "phase", "surface_colour", 1.5),
        ("lava_lamp", "phase", "thermal_expansion", 2.0),
        ("lava_lamp", "phase", "reference_temperature", -300.0),
        ("diffusion", "fluid", "temperature", -300.0),
        ("lava_lamp", "fluid", "jitter", 0.6),
        ("dam_break", "fluid", "velocity", [1e5, 0.0, 0.0]),
        ("boiling", "fluid", "wall_margin", 2.5),
        ("water_oil", "fluid", "fractions", [0.5, 1.5]),
        ("two_fluids_mixed", "fluid", "seed", -7),
        ("water_oil", "scene", "end_time", -8.0),
        ("pour_glass", "scene", "frame_rate", 20000.0),
        ("lava_lamp", "render", "width", 4),
        ("dam_break", "render", "height", 20000),
        ("lava_lamp", "render", "samples", 0),
        ("dam_break", "render", "fov", 180.0),
        ("lava_lamp", "render.material.wax", "ior", 0.5),
        ("lava_lamp", "render.material.fluid", "priority", -1),
        ("dam_break", "render.material.tank", "thickness", 11.0),
        ("lava_lamp", "surfacing", "voxel_ratio", 0.01),
        ("water_oil", "effects.pressure", "gradient_correction", 2.0),
        ("dam_break", "effects.viscosity", "stability_factor", 0.0),
        ("pour_glass", "effects.emitter.disc", "radius", 0.0),
        ("pour_glass", "effects.trapped_air", "distance", 2.0),
        ("boiling", "effects.phase_change", "site_radius", 11.0),
        ("boiling", "effects.flame_heating", "flame_rate", -0.5),
        ("water_oil", "effects.interface_tension", "model", 3.0),
        ("boiling", "effects.buoyancy.gas", "coefficient", -1.0),
        ("boiling", "effects.emitter.disc", "temperature", -300.0),
    ]
    for cfg, sec, key, v in oor:
        one(corpus, c, "out_of_range", cfg, sec, key, v)
    # Relations between keys.
    dmin = c.doc["dam_break"]["scene"]["domain_min"]
    d = c.edit("dam_break").set("scene", "domain_max", dmin)
    corpus.add("out_of_range", "dam_break", "scene.domain_max = %s equal to domain_min" % tv(dmin), d.text(), expect="key:scene.domain_max",
               sets=[(("scene", "domain_max"), dmin)])
    d = c.edit("water_oil").set("fluid", "max", [0.2, -0.15, 0.1])
    corpus.add("out_of_range", "water_oil", "fluid[0].max = [0.2, -0.15, 0.1] below its min", d.text(), expect="key:fluid[0].max",
               sets=[(("fluid", 0, "max"), [0.2, -0.15, 0.1])])
    d = c.edit("diffusion").set("solid", "max", [0.2, -0.1, 0.1])
    corpus.add("out_of_range", "diffusion", "solid[0].max = [0.2, -0.1, 0.1] below its min", d.text(), expect="key:solid[0].max",
               sets=[(("solid", 0, "max"), [0.2, -0.1, 0.1])])
    d = c.edit("lava_lamp").set("solver", "min_dt", 0.01)
    corpus.add("out_of_range", "lava_lamp", "solver.min_dt = 0.01 above max_dt 0.004", d.text(), expect="key:solver.min_dt",
               sets=[(("solver", "min_dt"), 0.01)])
    d = c.edit("pour_glass").set("effects.emitter.disc", "start", 2.0)
    corpus.add("out_of_range", "pour_glass", "effects.emitter.disc[0].start = 2.0 after its end 0.9", d.text(),
               expect="key:effects.emitter.disc[0].end", sets=[(("effects", "emitter", "disc", 0, "start"), 2.0)])
    d = c.edit("lava_lamp").set("solid", "profile", [[0.0, 0.13], [0.8, 0.17], [0.35, 0.15], [1.15, 0.1]])
    corpus.add("out_of_range", "lava_lamp", "solid[0].profile heights not increasing (0, 0.8, 0.35, 1.15)", d.text(),
               expect="key:solid[0].profile", post=lambda doc: doc["solid"][0]["profile"][2][0] == 0.35)
    d = c.edit("lava_lamp").set("solid", "profile", [[0.0, 0.13], [0.35, -0.17], [0.8, 0.15], [1.15, 0.1]])
    corpus.add("out_of_range", "lava_lamp", "solid[0].profile radius -0.17", d.text(), expect="key:solid[0].profile",
               post=lambda doc: doc["solid"][0]["profile"][1][1] == -0.17)
    one(corpus, c, "out_of_range", "water_oil", "scene", "frame_rate", 0.0, note="no frame rate (the range today includes 0)")
    one(corpus, c, "out_of_range", "boiling", "effects.phase_change", "up", [0.0, 0.0, 0.0])
    one(corpus, c, "out_of_range", "boiling", "effects.phase_change", "vapour", "water", note="same as liquid")


def gen_random(corpus, c, rng):
    for n in [1, 7, 100, 1000, 65536]:
        data = bytes(rng.randrange(256) for _ in range(n))
        corpus.add("random_bytes", None, "%d random bytes" % n, data, check="none")
    data = "".join(chr(rng.randrange(32, 127)) if rng.random() > 0.05 else "\n" for _ in range(4000))
    corpus.add("random_bytes", None, "4000 random printable ASCII characters and newlines", data, check="none")
    corpus.add("random_bytes", None, "empty file (0 bytes)", b"", check="none")
    corpus.add("random_bytes", None, "a UTF-8 byte order mark only", b"\xef\xbb\xbf", check="none")
    for cfg in ["dam_break", "lava_lamp"]:
        junk = b"\xff" + bytes(rng.randrange(256) for _ in range(500))
        corpus.add("random_bytes", cfg, "501 random bytes (starting FF) appended", c.text[cfg].encode() + b"\n" + junk, check="invalid")
    for cfg in ["water_oil", "boiling"]:
        d = c.edit(cfg)
        li = rng.randrange(len(d.lines))
        junk = b"\xfe" + bytes(rng.randrange(256) for _ in range(200))
        before = ("\n".join(d.lines[:li]) + "\n").encode()
        after = ("\n".join(d.lines[li:])).encode()
        corpus.add("random_bytes", cfg, "201 random bytes (starting FE) inserted before line %d" % (li + 1), before + junk + after, check="invalid")
    for cfg in ["pour_glass", "two_fluids_mixed"]:
        b = bytearray(c.text[cfg].encode())
        flips = 0
        for i in range(rng.randrange(20), len(b), 97):
            if b[i] < 0x80:
                b[i] |= 0x80
                flips += 1
        corpus.add("random_bytes", cfg, "high bit set on %d isolated bytes (every 97th)" % flips, bytes(b), check="invalid")
    corpus.add("random_bytes", "diffusion", "encoded as UTF-16 with a byte order mark", c.text["diffusion"].encode("utf-16"), check="invalid")
    corpus.add("random_bytes", "dam_break", "line ends replaced by NUL bytes", c.text["dam_break"].replace("\n", "\0").encode(), check="invalid")
    data = b"[scene]\n" + bytes(rng.randrange(256) for _ in range(3000))
    corpus.add("random_bytes", None, "'[scene]' and 3000 random bytes", data, check="none")


def gen_huge(corpus, c, rng, mb):
    size = mb * 1024 * 1024
    # 1: comments, then a syntax error at the end.
    head = c.text["lava_lamp"]
    line = "# " + "padding " * 12 + "\n"
    body = line * ((size - len(head)) // len(line))
    corpus.add("huge_file", "lava_lamp", "%d MB: %d comment lines, then 'cfl = = 0.4' at the end" % (mb, body.count("\n")),
               head + body + "cfl = = 0.4\n", check="none")
    # 2: a scene name of 50 MB.
    d = c.edit("dam_break").replace_key_line("scene", "name", 'name = "' + "x" * size + '"')
    corpus.add("huge_file", "dam_break", "scene.name = \"xxx...\" of %d MB" % mb, d.text(), expect="key:scene.name", check="none")
    # 3: a vessel profile of ~2 million points.
    n = size // 20
    pts = ", ".join("[%.7f, 0.15]" % (1.15 * i / n) for i in range(n))
    d = c.edit("lava_lamp").replace_key_line("solid", "profile", "profile = [" + pts + "]")
    corpus.add("huge_file", "lava_lamp", "solid[0].profile of %d points (%d MB)" % (n, mb), d.text(), expect="line", check="none")
    # 4: an unknown key with an array of 10 million numbers.
    n = size // 5
    d = c.edit("water_oil").add_line("", "junk = [" + "0.0, " * n + "]")
    corpus.add("huge_file", "water_oil", "top-level unknown key junk = [0.0, ...] of %d numbers (%d MB)" % (n, mb), d.text(),
               expect="key:junk", check="none")
    # 5: fluid blocks, ~700 000 of them.
    block = '[[fluid]]\nphase = "water"\nmin = [0.0, 0.0, 0.0]\nmax = [0.05715, 0.1143, 0.05715]\n'
    n = size // len(block)
    corpus.add("huge_file", "dam_break", "%d more [[fluid]] blocks (%d MB)" % (n, mb), c.text["dam_break"] + "\n" + block * n,
               expect="line", check="none")
    # 6: one table header nested millions of levels deep.
    n = size // 2
    corpus.add("huge_file", "pour_glass", "unknown table [a.a.a...] %d levels deep (%d MB)" % (n, mb),
               c.text["pour_glass"] + "\n[" + ".".join(["a"] * n) + "]\nx = 1\n", expect="line", check="none")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=20240611)
    ap.add_argument("--configs", default=os.path.normpath(os.path.join(HERE, "..", "..", "configs")))
    ap.add_argument("--no-huge", action="store_true", help="leave out the huge files")
    ap.add_argument("--huge-mb", type=int, default=50)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rng = random.Random(args.seed)
    c = Configs(args.configs)
    corpus = Corpus(args.out)
    for gen in [gen_crashes, gen_hangs, gen_zero, gen_other_measured, gen_names, gen_syntax, gen_truncations,
                gen_wrong_types, gen_unknown_keys, gen_duplicates, gen_numbers, gen_random]:
        gen(corpus, c, rng)
    if not args.no_huge:
        gen_huge(corpus, c, rng, args.huge_mb)
    corpus.write_index()
    counts = {}
    for e in corpus.entries:
        counts[e[1]] = counts.get(e[1], 0) + 1
    print("make_corpus: %d scenes in %s (%s)" % (len(corpus.entries), args.out,
                                                ", ".join("%s %d" % kv for kv in counts.items())))


if __name__ == "__main__":
    main()
