#!/usr/bin/python3
"""Self-test of tools/riffle-tools scene-keys (riffle_tools.scene_keys) on a synthetic SCENES.md and a synthetic
`riffle keys` output, no riffle needed: a correct doc passes; an undocumented key, a stale documented key and a wrong
default are each caught, naming the doc's line; the normalisation of defaults (numbers to 6 digits, fractions,
inf, none = required, probe-kind prefixes, defaults that follow another key); and the command end to end through a
stand-in for riffle (exit 0 / 1 and the "N keys checked, M problems" line).

Usage: /usr/bin/python3 tests/tools/test_scene_keys.py [WORK_DIR]   (exit 0 = pass)
"""
import os
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from riffle_tools import scene_keys  # noqa: E402

failures = []


def check(condition, text):
    print(("ok - " if condition else "FAIL - ") + text)
    if not condition:
        failures.append(text)


KEYS = "\n".join("\t".join(fields) for fields in [
    ("key", "kind", "range", "unit", "default", "given"),
    ("run", "table", "", "", "required", "yes"),
    ("run.dt", "number", "a number > 0", "s", "required", "yes"),
    ("run.gravity", "3 numbers", "a finite number", "m/s^2", "[0, 0, -9.81]", "no"),
    ("run.name", "string", "", "", '"riffle"', "no"),
    ("run.tolerance", "number", "a number > 0", "1", "1e-08", "no"),
    ("run.exponent", "number", "a number > 0", "1", "0.142857", "no"),
    ("run.hold", "number", "a number >= 0", "s", "required", "yes"),
    ("run.walls", "boolean", "", "", "true", "no"),
    ("materials", "table", "", "", "required", "yes"),
    ("materials.NAME.density", "number", "a number > 0", "kg/m^3", "required", "yes"),
    ("materials.NAME.young_modulus", "number", "a number >= 0", "Pa", "0 | required", "yes"),
    ("boxes", "tables", "", "", "[]", "yes"),
    ("boxes[].low", "3 numbers", "a finite number", "m", "required", "yes"),
    ("boxes[].velocity", "3 numbers", "a finite number", "m/s", "[0, 0, 0]", "no"),
    ("walls", "tables", "", "", "[]", "yes"),
    ("walls[].low", "3 numbers", "a finite number", "m", "required", "yes"),
    ("walls[].velocity", "number", "a finite number", "m/s", "0", "no"),
    ("probes", "tables", "", "", "[]", "yes"),
    ("probes[].below", "number", "a number > 0", "m", "inf", "no"),
    ("probes[].radius", "number", "a number > 0", "m", "0.005 | 0.01", "no"),
    ("probes[].file", "string", "", "", '"probe_a.csv" | "probe_b.csv"', "no"),
    ("probes[].classes", "tables", "", "", "[]", "yes"),
    ("probes[].classes[].count", "integer", "[0, 50000000]", "", "required", "yes"),
]) + "\n"

DOC = """# Scene files

## `[run]` (required; not `[materials]`)

| key | type | default | meaning |
|---|---|---|---|
| `dt` | number > 0 [s] | required | the step |
| `gravity` | 3 numbers [m/s²] | `[0, 0, -9.81]` | |
| `name` | string | `"riffle"` | |
| `tolerance` | number | 1e-8 | a tolerance |
| `exponent` | number | 1/7 | n |
| `hold` | number [s] | none | hold the grains until then |
| `walls` | boolean | `true` | |

## `[materials.NAME]` (at least one)

| key | type | default |
|---|---|---|
| `density` | number > 0 [kg/m³] | required |
| `young_modulus` | number > 0 [Pa] | required with `[contact]`, else 0 |

### `[[boxes]]` (at least one) and `[[walls]]` (any number)

| key | type | default | meaning |
|---|---|---|---|
| `low` | 3 numbers [m] | required | |
| `velocity` | 3 numbers [m/s] | `[0, 0, 0]` | boxes only |
| `velocity` | number [m/s] | 0 | walls only |

### `[[probes]]`

| key | type | default | meaning |
|---|---|---|---|
| `below` | number > 0 [m] | `"surge_front"`: ∞ (the whole depth) | |
| `radius` | number > 0 [m] | `"wave_gauge"`: l0 (the fluid's spacing) | |
| `file` | plain file name | `probe_<name>.csv` | |

```toml
[run]
| `in_code` | not a table | row |
```

`[[probes.classes]]`, one per class:

| key | type | default | meaning |
|---|---|---|---|
| `count` | integer | required | |

| | seed | riffle |
|---|---|---|
| `box` | 2 cm | 4 cm |
"""


def run_check(doc, keys=KEYS):
    problems, count = scene_keys.check(doc, keys, "SCENES.md")
    return problems, count


def line_of(doc, text):
    return doc.splitlines().index(next(line for line in doc.splitlines() if text in line)) + 1


def check_parse():
    keys, tables, _ = scene_keys.parse_doc(DOC)
    prefixes = [t.prefixes for t in tables]
    check(prefixes == [["run"], ["materials.NAME"], ["boxes", "walls"], ["probes"], ["probes.classes"]],
          f"key tables and their prefixes (headings, a paragraph naming its table; not the code block or a table "
          f"whose first column is not `key`): {prefixes}")
    check(not any(k.key[1] in ("in_code", "box") for k in keys), "a code block and a non-key table document nothing")


def check_correct_doc():
    problems, count = run_check(DOC)
    check(problems == [], f"a correct doc passes: {problems}")
    check(count == 23, f"every key of `riffle keys` counted: {count}")


def check_undocumented():
    doc = DOC.replace("| `walls` | boolean | `true` | |\n", "")
    problems, _ = run_check(doc)
    line = line_of(doc, "| key | type | default | meaning |")
    check(len(problems) == 1 and problems[0].startswith(f"SCENES.md:{line}: run.walls: not documented"),
          f"an undocumented key is caught at its table's line: {problems}")
    keys = KEYS + "probes[].classes[].material\tstring\t\t\trequired\tyes\n"
    problems, _ = run_check(DOC, keys)
    line = line_of(DOC, "| `count` | integer | required | |") - 2
    check(len(problems) == 1 and f"SCENES.md:{line}: probes[].classes[].material: not documented" in problems[0],
          f"an undocumented key of a nested array of tables: {problems}")
    keys = KEYS + "fluid\ttable\t\t\tabsent\tno\n"
    problems, _ = run_check(DOC, keys)
    check(len(problems) == 1 and "fluid: the reading asks this table but no key table documents it" in problems[0],
          f"an undocumented table: {problems}")


def check_stale():
    doc = DOC.replace("| `walls` | boolean | `true` | |\n", "| `walls` | boolean | `true` | |\n"
                                                          "| `old_key` | number | 1 | gone |\n")
    problems, _ = run_check(doc)
    line = line_of(doc, "`old_key`")
    check(problems == [f"SCENES.md:{line}: run.old_key: documented but never asked by the samples' reading (stale "
                       f"doc, or no sample sets it up)"], f"a stale documented key is caught: {problems}")
    keys = "\n".join(line for line in KEYS.splitlines() if not line.startswith("walls")) + "\n"
    check(run_check(DOC, keys)[0] == [], "a row of a heading naming two tables is not stale while one table asks it")
    keys = "\n".join(line for line in KEYS.splitlines() if "[].low" not in line) + "\n"
    problems, _ = run_check(DOC, keys)
    check(len(problems) == 1 and ": boxes[].low, walls[].low: documented but never asked" in problems[0],
          f"... and stale, once, where neither asks it: {problems}")
    doc = DOC.replace("| `dt` |", "| `initial_state` | string | none | |\n| `dt` |")
    problems, _ = run_check(doc)
    check(any("run.initial_state" in p for p in problems), "only solids.initial_state is excused from coverage")


def check_defaults():
    cases = [
        ("| `tolerance` | number | 1e-8 |", "| `tolerance` | number | 1e-7 |",
         "run.tolerance: the doc's default is 1e-7"),
        ("| `gravity` | 3 numbers [m/s²] | `[0, 0, -9.81]` |", "| `gravity` | 3 numbers [m/s²] | `[0, 0, -9.8]` |",
         "run.gravity"),
        ('| `name` | string | `"riffle"` |', '| `name` | string | `"run"` |', "run.name"),
        ("| `walls` | boolean | `true` |", "| `walls` | boolean | `false` |", "run.walls"),
        ("| `dt` | number > 0 [s] | required |", "| `dt` | number > 0 [s] | 0.001 |", "run.dt"),
        ("| `hold` | number [s] | none |", "| `hold` | number [s] | 0 |", "run.hold"),
        ("| `exponent` | number | 1/7 |", "| `exponent` | number | 1/6 |", "run.exponent"),
        ("| `young_modulus` | number > 0 [Pa] | required with `[contact]`, else 0 |",
         "| `young_modulus` | number > 0 [Pa] | required |", "does not mention 0"),
        ("| `below` | number > 0 [m] | `\"surge_front\"`: ∞ (the whole depth) |",
         "| `below` | number > 0 [m] | `\"surge_front\"`: the whole depth |", "is not a value"),
        ("| `velocity` | number [m/s] | 0 | walls only |", "| `velocity` | number [m/s] | 1 | walls only |",
         "walls[].velocity"),
    ]
    for old, new, expected in cases:
        assert old in DOC, old
        doc = DOC.replace(old, new)
        problems, _ = run_check(doc)
        line = line_of(doc, new)
        check(len(problems) == 1 and problems[0].startswith(f"SCENES.md:{line}: ") and expected in problems[0],
              f"a wrong default is caught ({new.split('|')[1].strip()} -> {new.split('|')[3].strip()}): {problems}")
    # A default that follows another key: a literal cell must mention each of the code's values.
    doc = DOC.replace("`\"wave_gauge\"`: l0 (the fluid's spacing)", "0.005")
    problems, _ = run_check(doc)
    check(len(problems) == 1 and "probes[].radius" in problems[0] and "does not mention 0.01" in problems[0],
          f"a literal default that misses one of the code's: {problems}")
    doc = DOC.replace("`\"wave_gauge\"`: l0 (the fluid's spacing)", "0.005 at l0 = 5 mm, 0.01 at 10 mm")
    check(run_check(doc)[0] == [], "a cell that mentions each of the code's defaults passes")


def check_normalisation():
    check(scene_keys.leading_value('`"surge_front"`: inf (the whole depth)') == ("inf", True), "probe-kind prefix")
    check(scene_keys.leading_value("0 = half the smallest radius") == ("0", True), "a leading number")
    check(scene_keys.leading_value("`end_time` / 10") == ("end_time", False), "a key name is a description")
    check(scene_keys.leading_value("the table's `friction`")[1] is False, "a phrase is a description")
    check(scene_keys.literal("[contact]") is None, "a backticked table name is not a list")
    check(scene_keys.default_problem("1e-6", ["1e-06"]) is None, "1e-6 = 1e-06")
    check(scene_keys.default_problem("0.142857", ["0.142857"]) is None, "same spelling")
    check(scene_keys.default_problem("\u22121", ["-1"]) is None, "U+2212 minus")
    check(scene_keys.default_problem("—", ["required"]) is None, "— = no default")
    check(scene_keys.default_problem("required", ["0"]) is not None, "required is not 0")
    check(scene_keys.default_problem('`"a"`', ['"b"']) is not None, "strings compare exactly")


def check_command(work):
    fake = work / "fake-riffle"
    (work / "keys.tsv").write_text(KEYS)
    fake.write_text(f"#!/bin/sh\n[ \"$1\" = keys ] || exit 1\ncat '{work / 'keys.tsv'}'\n")
    os.chmod(fake, 0o755)
    (work / "good.md").write_text(DOC)
    (work / "bad.md").write_text(DOC.replace("| `tolerance` | number | 1e-8 |", "| `tolerance` | number | 1e-7 |"))
    tool = [sys.executable, str(ROOT / "tools" / "riffle-tools"), "scene-keys", "--riffle", str(fake)]
    good = subprocess.run([*tool, "--doc", str(work / "good.md"), "a.toml"], capture_output=True, text=True)
    check(good.returncode == 0 and good.stdout.strip() == "23 keys checked, 0 problems",
          f"the command passes a correct doc: {good.returncode} {good.stdout!r} {good.stderr!r}")
    bad = subprocess.run([*tool, "--doc", str(work / "bad.md"), "a.toml"], capture_output=True, text=True)
    lines = bad.stdout.strip().splitlines()
    check(bad.returncode == 1 and len(lines) == 2 and "bad.md:" in lines[0] and "run.tolerance" in lines[0]
          and lines[1] == "23 keys checked, 1 problems", f"the command fails a wrong doc: {bad.stdout!r}")
    fake.write_text("#!/bin/sh\necho 'error: a.toml:1:1: run: bad' >&2\nexit 2\n")
    invalid = subprocess.run([*tool, "--doc", str(work / "good.md"), "a.toml"], capture_output=True, text=True)
    check(invalid.returncode == 1 and "a.toml:1:1" in invalid.stderr, "an invalid sample fails the command")


def main():
    with tempfile.TemporaryDirectory() as scratch:
        work = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(scratch)
        work.mkdir(parents=True, exist_ok=True)
        check_parse()
        check_correct_doc()
        check_undocumented()
        check_stale()
        check_defaults()
        check_normalisation()
        check_command(work)
    print(f"{len(failures)} failures" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
