#!/usr/bin/python3
"""Self-test of tools/riffle-tools scene-keys (riffle_tools.scene_keys) on a synthetic SCENES.md and a synthetic
`riffle keys` output, no riffle needed: a doc as the reading writes it is left as it is; the type and one-value
default cells are written from the reading, the doc's own columns and the defaults the code does not state as one
value are kept and checked; new keys are added (and flagged without a description), stale ones dropped, equal rows
joined; the prose outside the markers is not touched; what is left for a person is named at the doc's line; and the
command end to end through a stand-in for riffle (check and --write, exit 0 / 1, the command that rewrites).

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
    ("run.tolerance", "number", "a number in (0, 1)", "1", "1e-08", "no"),
    ("run.hold", "number", "a number >= 0", "s", "required", "yes"),
    ("run.steps", "integer", "[1, 1000000]", "", "10", "no"),
    ("run.walls", "boolean", "", "", "true", "no"),
    ("run.law", "one of", '"hertz", "linear"', "", '"hertz"', "no"),
    ("run.faces", "list of", '"x", "y"', "", "[]", "no"),
    ("run.ids", "integers", "[0, 9223372036854775807]", "", "required", "yes"),
    ("run.coefficient", "number", "a number in (0, 1] | a number in (0, 10]", "1", "0.25 | 2", "no"),
    ("solids", "table", "", "", "absent", "yes"),
    ("solids.sort_every", "integer", "[0, 1000000000]", "", "0", "no"),
    ("materials", "table", "", "", "required", "yes"),
    ("materials.NAME.density", "number", "a number > 0", "kg/m^3", "required", "yes"),
    ("materials.NAME.young_modulus", "number", "a number > 0", "Pa", "0 | required", "yes"),
    ("boxes", "tables", "", "", "[]", "yes"),
    ("boxes[].low", "3 numbers", "a finite number", "m", "required", "yes"),
    ("boxes[].high", "3 numbers", "a finite number", "m", "required", "yes"),
    ("boxes[].bottom", "number", "a number in the tank's z extent", "m", "required", "yes"),
    ("boxes[].classes", "tables", "", "", "[]", "yes"),
    ("boxes[].classes[].count", "integer", "[0, 50000000]", "", "required", "yes"),
]) + "\n"

DOC = """# Scene files

Prose before, with a table that is not a key table:

| key | seed | riffle |
|---|---|---|
| `box` | 2 cm | 4 cm |

## `[run]`

<!-- scene-keys run -->
| key | type | default | meaning |
|---|---|---|---|
| `dt` | number > 0 [s] | required | the step |
| `gravity` | 3 numbers [m/s²] | `[0, 0, -9.81]` | g |
| `name` | string | `"riffle"` | the run's name |
| `tolerance` | number in (0, 1) [1] | 1e-8 | a tolerance |
| `hold` | number ≥ 0 [s] | none | hold the grains until then |
| `steps` | integer 1–1e6 | 10 | steps |
| `walls` | boolean | `true` | walls |
| `law` | `"hertz"` or `"linear"` | `"hertz"` | the law |
| `faces` | strings from `"x"`, `"y"` | `[]` | open faces |
| `ids` | integers ≥ 0 | required for `"grains"` | grain ids |
| `coefficient` | number in (0, 1] or in (0, 10] [1] | 2 (`"velocity"`), 0.25 (`"constant"`) | A |
<!-- /scene-keys -->

## `[solids]`

<!-- scene-keys solids -->
| key | type | default | meaning |
|---|---|---|---|
| `sort_every` | integer 0–1e9 | 0 | reorder grains |
| `initial_state` | string (path) | none | a checkpoint's grains |
<!-- /scene-keys -->

```toml
[run]
| `in_code` | not a table | row |
```

## `[materials.NAME]`

<!-- scene-keys materials.NAME -->
| key | type | default | meaning | note |
|---|---|---|---|---|
| `density` | number > 0 [kg/m³] | required | ρ | |
| `young_modulus` | number > 0 [Pa] | required with `[contact]`, else 0 | E | stiff |
<!-- /scene-keys -->

## `[[boxes]]`

<!-- scene-keys boxes[] -->
| key | type | default | meaning |
|---|---|---|---|
| `low`, `high` | 3 numbers [m] | required | corners |
| `bottom` | number in the tank's z extent [m] | required | z0 |
<!-- /scene-keys -->

`[[boxes.classes]]`:

<!-- scene-keys boxes[].classes[] -->
| key | type | default | meaning |
|---|---|---|---|
| `count` | integer 0–5e7 | required | grains |
<!-- /scene-keys -->

Prose after.
"""

KEY_COUNT = 23


def generate(doc, keys=KEYS):
    return scene_keys.generate(doc, keys, "SCENES.md")


def line_of(doc, text):
    return next(number for number, line in enumerate(doc.splitlines(), 1) if text in line)


def check_as_written():
    written, problems = generate(DOC)
    check(problems == [], f"a doc as the reading writes it has nothing left for a person: {problems}")
    check(written == DOC, "... and is written back as it is (prose, a code block and a non-key table untouched)")


def check_written_cells():
    cases = [
        ("| `dt` | number > 0 [s] |", "| `dt` | number [s] |", "a wrong type"),
        ("| `steps` | integer 1–1e6 | 10 |", "| `steps` | integer 1–1e6 | 12 |", "a wrong one-value default"),
        ("| `tolerance` | number in (0, 1) [1] | 1e-8 |", "| `tolerance` | number in (0, 1) [1] | 1e-7 |",
         "a wrong number default"),
        ("| `walls` | boolean | `true` |", "| `walls` | boolean | false |", "a wrong boolean default"),
        ("| `law` | `\"hertz\"` or `\"linear\"` |", "| `law` | `\"hertz\"` |", "a wrong choice list"),
        ("| `low`, `high` | 3 numbers [m] | required | corners |",
         "| `low` | 3 numbers [m] | required | corners |\n| `high` | 3 numbers [m] | required | corners |",
         "two rows of equal cells (joined)"),
    ]
    for old, new, what in cases:
        assert old in DOC, old
        doc = DOC.replace(old, new)
        written, problems = generate(doc)
        check(written == DOC and problems == [], f"{what} is written from the reading: {problems}")


def check_new_and_stale():
    doc = DOC.replace("| `walls` | boolean | `true` | walls |\n", "")
    written, problems = generate(doc)
    check(written.splitlines()[line_of(written, "| `coefficient` |")] == "| `walls` | boolean | `true` | |",
          "a new key is added after the doc's rows, its description empty")
    line = line_of(doc, "<!-- scene-keys run -->")
    check(problems == [f"SCENES.md:{line}: run.walls: no description (write one in the `meaning` column)"],
          f"... and flagged at its table: {problems}")
    doc = DOC.replace("| `walls` | boolean | `true` | walls |\n",
                      "| `walls` | boolean | `true` | walls |\n| `old_key` | number | 1 | gone |\n")
    written, problems = generate(doc)
    check(written == DOC and problems == [], f"a key the samples never ask is dropped: {problems}")
    keys = "".join(line + "\n" for line in KEYS.splitlines() if not line.startswith("run.walls"))
    written, _ = generate(DOC, keys)
    check("`walls`" not in written and "| `initial_state` | string (path) | none | a checkpoint's grains |" in written,
          "a key no longer asked goes; the row of solids.initial_state, which no sample can ask, stays as written")


def check_kept_defaults():
    doc = DOC.replace("| required with `[contact]`, else 0 |", "| required |")
    problems = generate(doc)[1]
    line = line_of(doc, "| `young_modulus` |")
    check(len(problems) == 1 and problems[0].startswith(f"SCENES.md:{line}: materials.NAME.young_modulus: ")
          and "does not mention 0" in problems[0], f"a kept default missing one of the code's values: {problems}")
    doc = DOC.replace("| `hold` | number ≥ 0 [s] | none |", "| `hold` | number ≥ 0 [s] | 0 |")
    problems = generate(doc)[1]
    check(len(problems) == 1 and "run.hold: the doc's default is '0'" in problems[0],
          f"a value where the code reads the key without a default: {problems}")
    doc = DOC.replace("| 2 (`\"velocity\"`), 0.25 (`\"constant\"`) |", "| 2 |")
    problems = generate(doc)[1]
    check(len(problems) == 1 and "run.coefficient" in problems[0] and "does not mention 0.25" in problems[0],
          f"a default that follows another key must mention each value: {problems}")
    written, problems = generate(DOC.replace("| ρ | |", "| | |"))
    check(any("materials.NAME.density: no description" in p for p in problems), "an emptied description is flagged")
    check("| `young_modulus` | number > 0 [Pa] | required with `[contact]`, else 0 | E | stiff |" in written,
          "the doc's own columns beyond the first are kept")


def check_coverage():
    keys = KEYS + "tank\ttable\t\t\trequired\tyes\ntank.size\t3 numbers\ta number > 0\tm\trequired\tyes\n"
    problems = generate(DOC, keys)[1]
    check(len(problems) == 2 and any("tank: the reading asks this table but no key table documents it" in p
                                     for p in problems)
          and any("tank.size: no key table for `tank`" in p for p in problems),
          f"a key and a table no block covers: {problems}")
    doc = DOC.replace("<!-- scene-keys boxes[].classes[] -->", "<!-- scene-keys boxes[].kinds[] -->")
    problems = generate(doc)[1]
    check(any("boxes[].kinds[]: the samples' reading asks no key in this table" in p for p in problems)
          and any("boxes[].classes[].count: no key table for `boxes[].classes[]`" in p for p in problems),
          f"a block with a wrong prefix: {problems}")
    doc = DOC.replace("| `count` | integer 0–5e7 | required | grains |\n<!-- /scene-keys -->",
                      "| `count` | integer 0–5e7 | required | grains |")
    problems = generate(doc)[1]
    check(any("start marker without <!-- /scene-keys -->" in p for p in problems), f"an unclosed block: {problems}")


def check_cells():
    code = scene_keys.CodeKey
    cases = [
        (code("a", "number", ["a finite number"], "m", ["0"]), "number [m]"),
        (code("a", "number", ["a number >= 0"], "m^2/s", ["0"]), "number ≥ 0 [m²/s]"),
        (code("a", "number", ["a number in [4, 1e+06]"], "1", ["0"]), "number in [4, 1e6] [1]"),
        (code("a", "3 numbers", ["a number > 0"], "m", ["0"]), "3 numbers > 0 [m]"),
        (code("a", "integer", ["[0, 1000000000]"], "", ["0"]), "integer 0–1e9"),
        (code("a", "integers", ["[0, 9223372036854775807]"], "", ["0"]), "integers ≥ 0"),
        (code("a", "one of", ['"a", "b", "c"'], "", ["0"]), '`"a"`, `"b"` or `"c"`'),
        (code("a", "list of", ["the material names"], "", ["[]"]), "strings from the material names"),
        (code("a", "points", ["3 numbers each"], "m", ["required"]), "array of points [m]"),
    ]
    for key, expected in cases:
        check(scene_keys.type_cell(key) == expected, f"type cell {expected!r}: {scene_keys.type_cell(key)!r}")
    for default, expected in (("1e-06", "1e-6"), ("inf", "∞"), ("0.142857", "0.142857"), ("true", "`true`"),
                              ('"a"', '`"a"`'), ("[0, 0, 0]", "`[0, 0, 0]`")):
        check(scene_keys.default_value(default) == expected, f"default {default} written {expected}")


def check_normalisation():
    check(scene_keys.leading_value('`"surge_front"`: inf (the whole depth)') == ("inf", True), "probe-kind prefix")
    check(scene_keys.leading_value("`end_time` / 10") == ("end_time", False), "a key name is a description")
    check(scene_keys.leading_value("the table's `friction`")[1] is False, "a phrase is a description")
    check(scene_keys.default_problem("—", ["required"]) is None, "— = no default")
    check(scene_keys.default_problem("0.005 at l0 = 5 mm, 0.01 at 10 mm", ["0.005", "0.01"]) is None,
          "a cell that mentions each of the code's defaults")
    check(scene_keys.default_problem("l0 (the fluid's spacing)", ["0.005", "0.01"]) is None,
          "a cell that leads with a description need mention no value")
    check(scene_keys.default_problem("l0", ["0.005", "required"]) is not None, "... but must mention required")


def check_command(work):
    fake = work / "fake-riffle"
    (work / "keys.tsv").write_text(KEYS)
    fake.write_text(f"#!/bin/sh\n[ \"$1\" = keys ] || exit 1\ncat '{work / 'keys.tsv'}'\n")
    os.chmod(fake, 0o755)
    good, bad = work / "good.md", work / "bad.md"
    good.write_text(DOC)
    bad.write_text(DOC.replace("| `steps` | integer 1–1e6 | 10 |", "| `steps` | integer 1–1e6 | 12 |"))
    tool = [sys.executable, str(ROOT / "tools" / "riffle-tools"), "scene-keys", "--riffle", str(fake)]
    run = subprocess.run([*tool, "--doc", str(good), "a.toml"], capture_output=True, text=True)
    check(run.returncode == 0 and run.stdout.strip() == f"{KEY_COUNT} keys read, 0 left for a person",
          f"the check passes a doc as written: {run.returncode} {run.stdout!r} {run.stderr!r}")
    run = subprocess.run([*tool, "--doc", str(bad), "a.toml"], capture_output=True, text=True)
    check(run.returncode == 1 and "-| `steps` | integer 1–1e6 | 12 |" in run.stdout
          and f"--doc {bad} --write a.toml" in run.stdout and "the tables differ" in run.stdout,
          f"the check fails a doc that differs, with the diff and the command that rewrites it: {run.stdout!r}")
    run = subprocess.run([*tool, "--doc", str(bad), "--write", "a.toml"], capture_output=True, text=True)
    check(run.returncode == 0 and bad.read_text() == DOC, f"--write rewrites it: {run.stdout!r}")
    bad.write_text(DOC.replace("| ρ | |", "| | |"))
    run = subprocess.run([*tool, "--doc", str(bad), "--write", "a.toml"], capture_output=True, text=True)
    check(run.returncode == 1 and "no description" in run.stdout, f"--write exits 1 while a person has work: "
                                                                   f"{run.stdout!r}")
    fake.write_text("#!/bin/sh\necho 'error: a.toml:1:1: run: bad' >&2\nexit 2\n")
    run = subprocess.run([*tool, "--doc", str(good), "a.toml"], capture_output=True, text=True)
    check(run.returncode == 1 and "a.toml:1:1" in run.stderr, "an invalid sample fails the command")


def main():
    with tempfile.TemporaryDirectory() as scratch:
        work = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(scratch)
        work.mkdir(parents=True, exist_ok=True)
        check_as_written()
        check_written_cells()
        check_new_and_stale()
        check_kept_defaults()
        check_coverage()
        check_cells()
        check_normalisation()
        check_command(work)
    print(f"{len(failures)} failures" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
