"""docs/SCENES.md's key tables, written from the scene reading: runs `RIFFLE keys SCENE...` (every key the reading of
the sample scenes asks for, with its kind, range, unit and default as the code applies them) and rewrites each key
table of the doc from it.

  tools/riffle-tools scene-keys --riffle build/riffle [--doc docs/SCENES.md] tests/data/scene_keys/*.toml
  tools/riffle-tools scene-keys --riffle build/riffle --write tests/data/scene_keys/*.toml

Without --write it checks: the doc must be what --write would make it (else exit 1, with the differing lines and
the command that rewrites it), and nothing may be left for a person to do (below). With --write it rewrites the
tables in place and lists what is left for a person (exit 1 if anything is).

The doc. A key table lies between `<!-- scene-keys PREFIX -->` and `<!-- /scene-keys -->`, each alone on its line;
PREFIX is the table as the reading names it: `run`, `materials.NAME`, `contact.pairs[]`,
`solids.layered_beds[].classes[]`. Everything outside the markers is the doc's own and left as it is. A table's
columns are `key`, `type`, `default`, then one or more columns of the doc's own (`meaning`): the first three are
written from the reading, the others are kept, row by row, keyed by the key's name.

A table's rows are the keys the reading asks directly in PREFIX (not in its sub-tables), one row each, in the
doc's order, new keys after them in name order; neighbouring rows whose cells after the key are equal are joined
into one (`min`, `max`). A documented key the samples never ask is dropped, except the keys of UNCOVERED, whose
rows are kept as written.

Written from the reading:
- `type`: the kind, its range (`number > 0`, `integer 1–1e6`, `"a"` or `"b"`) and its unit in brackets ([1]: a pure
  number);
- `default`: the code's default where it is one value (numbers as the code spells them, other values backticked).

Kept as the doc writes them, and checked against the reading:
- `default` where the code's is not one value: several (the default follows other keys: a probe's `radius` is the
  fluid's spacing), or `required`, which the reading also records for a key it reads only where a scene gives it
  (`none`, `unset` or `—` say so). Such a cell must say `required` (or `none`, `unset`, `—`) where that is among the
  code's defaults; one that leads with a value must mention each of the code's values (numbers to 6 significant
  digits, `1/7` a fraction; strings and lists as written), one that leads with a description (`l0`, `the table's
  friction`) need mention only `required` among them;
- the doc's own columns. An empty first one (`meaning`) is a key without a description.

Left for a person (one line each, naming the doc's line): a key without a description; a kept default that
disagrees with the code's; a key, or a table the reading asks, that no key table covers (add one with its markers
where it belongs); a key table whose PREFIX the reading never asks.
"""
import argparse
import dataclasses
import difflib
import math
import pathlib
import re
import shlex
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

# Keys the samples cannot ask: their rows are kept as the doc writes them.
UNCOVERED = {
    "solids.initial_state",  # needs a settled bed's checkpoint, which a sample scene cannot carry
}

TABLE_KINDS = ("table", "tables", "named tables")
GENERATED = ("key", "type", "default")
START = re.compile(r"^<!-- scene-keys (\S+) -->$")
END = "<!-- /scene-keys -->"


@dataclasses.dataclass
class CodeKey:
    key: str
    kind: str
    ranges: list   # one, or several where the range follows another key
    unit: str
    defaults: list


def read_keys(text):
    """`riffle keys` output (tab-separated, a header line) as {key: CodeKey}."""
    keys = {}
    lines = text.splitlines()
    if not lines or not lines[0].startswith("key\t"):
        raise ValueError("not the output of `riffle keys`: no header line")
    for line in lines[1:]:
        if not line.strip():
            continue
        fields = line.split("\t")
        if len(fields) != 6:
            raise ValueError(f"`riffle keys` line with {len(fields)} fields, not 6: {line!r}")
        keys[fields[0]] = CodeKey(fields[0], fields[1], fields[2].split(" | ") if fields[2] else [], fields[3],
                                  fields[4].split(" | "))
    return keys


# --- the doc's tables -------------------------------------------------------------------------------------------

@dataclasses.dataclass
class Block:
    prefix: str
    start: int          # index of the start marker's line
    end: int            # index of the end marker's line
    header: list        # the table's column names as written ([] if the block holds no table yet)
    rows: list          # [(line number, cells)]


def split_row(line):
    cells = re.split(r"(?<!\\)\|", line.strip())
    return [cell.strip() for cell in cells[1:-1]]


def row_keys(cell):
    return re.findall(r"`([A-Za-z0-9_]+)`", cell)


def parse_blocks(lines):
    """The marked key tables of the doc's lines: ([Block], [(line number, problem)])."""
    blocks, problems = [], []
    i = 0
    while i < len(lines):
        found = START.match(lines[i].strip())
        if not found:
            if lines[i].strip() == END:
                problems.append((i + 1, f"{END} without a start marker above it"))
            i += 1
            continue
        start = i
        j = i + 1
        while j < len(lines) and lines[j].strip() != END and not START.match(lines[j].strip()):
            j += 1
        if j == len(lines) or lines[j].strip() != END:
            problems.append((start + 1, f"a key table's start marker without {END} after it"))
            i = j
            continue
        table = [(k + 1, lines[k]) for k in range(start + 1, j) if lines[k].startswith("|")]
        header = [cell.lower() for cell in split_row(table[0][1])] if table else []
        rows = [(number, split_row(line)) for number, line in table[2:]]
        blocks.append(Block(found.group(1), start, j, header, rows))
        i = j + 1
    return blocks, problems


# --- the reading's cells ----------------------------------------------------------------------------------------

SUPERSCRIPTS = {"2": "²", "3": "³"}


def unit_text(unit):
    """ [m/s²] of the unit m/s^2; "" without one."""
    return " [" + re.sub(r"\^([23])", lambda m: SUPERSCRIPTS[m.group(1)], unit) + "]" if unit else ""


def number_text(text):
    """A number as the code spells it, exponents without + and leading zeros (1e+06 -> 1e6, 1e-06 -> 1e-6)."""
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("-" if m.group(1) == "-" else "") + m.group(2), text)


def integer_text(value):
    """An integer bound: 1000000 -> 1e6, 50000000 -> 5e7, small ones as they are."""
    if value >= 10000:
        digits = str(value)
        if digits[1:] == "0" * (len(digits) - 1):
            return f"{digits[0]}e{len(digits) - 1}"
    return str(value)


def range_text(text):
    """A number's range as the reading describes it (Bounds::describe), for the type cell: "" for any finite
    number, "> 0", "≥ 0", "in [0, 1]", "in the tank's z extent"."""
    text = text.removeprefix("a finite number").removeprefix("a number").strip()
    return number_text(text.replace(">=", "≥").replace("<=", "≤"))


def integer_range_text(text):
    found = re.match(r"^\[(-?\d+), (-?\d+)\]$", text)
    if not found:
        return text
    low, high = int(found.group(1)), int(found.group(2))
    if high >= 2**62:
        return f"≥ {integer_text(low)}"
    return f"{integer_text(low)}–{integer_text(high)}"


def choices_text(text, last=" or "):
    """'"a", "b", "c"' -> '`"a"`, `"b"` or `"c"`'; a description (the material names) as it is."""
    names = re.findall(r'"[^"]*"', text)
    if not names:
        return text
    quoted = [f"`{name}`" for name in names]
    return quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + last + quoted[-1]


def type_cell(code):
    kind, ranges, unit = code.kind, code.ranges or [""], unit_text(code.unit)
    if kind in ("number", "3 numbers"):
        described = " or ".join(text for text in (range_text(r) for r in ranges) if text)
        return kind + (" " + described if described else "") + unit
    if kind in ("integer", "integers"):
        return kind + " " + " or ".join(integer_range_text(r) for r in ranges) + unit
    if kind == "one of":
        return " or ".join(choices_text(r) for r in ranges)
    if kind == "list of":
        return "strings from " + " or ".join(choices_text(r, ", ") for r in ranges)
    if kind == "points":
        return "array of points" + unit
    return kind + unit  # boolean, string


def default_value(text):
    """One code default as the default cell writes it: numbers plain (inf as ∞), other values backticked."""
    if text == "inf":
        return "∞"
    if as_number(text) is not None:
        return number_text(text)
    return f"`{text}`"


def written_default(code):
    """The default cell the reading writes, or None where the doc keeps its own (not one value, or required)."""
    if len(code.defaults) != 1 or code.defaults[0] == "required":
        return None
    return default_value(code.defaults[0])


# --- kept defaults, checked -------------------------------------------------------------------------------------

NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")
NONE_WORDS = ("none", "unset", "—")


def normalise_cell(cell):
    cell = cell.replace("\u2212", "-").replace("∞", "inf").strip()
    cell = re.sub(r'^(`"[A-Za-z_]+"`(\s*,\s*`"[A-Za-z_]+"`)*)\s*:\s*', "", cell)  # probe-kind prefix
    return cell


def as_number(text):
    text = text.strip()
    if text in ("inf", "+inf"):
        return math.inf
    if text == "-inf":
        return -math.inf
    if NUMBER.match(text):
        return float(text)
    fraction = re.match(r"^([+-]?\d+)/(\d+)$", text)
    if fraction and int(fraction.group(2)) != 0:
        return int(fraction.group(1)) / int(fraction.group(2))
    return None


def same_number(a, b):
    if math.isinf(a) or math.isinf(b):
        return a == b
    return abs(a - b) <= 5e-6 * max(abs(a), abs(b)) or a == b


def literal(text):
    """(kind, value) of a scene literal, or None: ("number", float), ("required", None), ("bool", str),
    ("string", str), ("list", [items])."""
    text = text.strip()
    if text == "required" or text in NONE_WORDS:
        return ("required", None)
    if text in ("true", "false"):
        return ("bool", text)
    number = as_number(text)
    if number is not None:
        return ("number", number)
    if len(text) >= 2 and text[0] == '"' and text[-1] == '"' and '"' not in text[1:-1]:
        return ("string", text)
    if text.startswith("[") and text.endswith("]"):
        inner = text[1:-1].strip()
        items = [item.strip() for item in inner.split(",")] if inner else []
        if all(literal(item) is not None and literal(item)[0] in ("number", "string", "bool") for item in items):
            return ("list", items)
    return None


def same_literal(a, b):
    if a[0] != b[0]:
        return False
    if a[0] == "number":
        return same_number(a[1], b[1])
    if a[0] == "list":
        if len(a[1]) != len(b[1]):
            return False
        for x, y in zip(a[1], b[1]):
            nx, ny = as_number(x), as_number(y)
            if not (nx is not None and ny is not None and same_number(nx, ny)) and x != y:
                return False
        return True
    return a[1] == b[1]


def leading_value(cell):
    """The default cell's leading value (a literal's text, or the description's first word) and whether it is a
    literal."""
    cell = normalise_cell(cell)
    quoted = re.match(r"^`([^`]*)`", cell)
    text = quoted.group(1) if quoted else re.match(r"^[^\s,;:(]*", cell).group(0)
    return text, literal(text) is not None


def mentions(cell, default):
    """Whether the cell mentions one code default (a number anywhere, a word or string as written)."""
    cell = normalise_cell(cell)
    code = literal(default)
    if code is None:
        return default in cell
    if code[0] == "required":
        return "required" in cell or any(re.search(r"(^|\W)" + re.escape(w) + r"(\W|$)", cell) for w in NONE_WORDS)
    if code[0] == "number":
        for token in re.findall(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?(?:/\d+)?|inf", cell):
            number = as_number(token)
            if number is not None and same_number(number, code[1]):
                return True
        return False
    if code[0] == "string":
        return code[1] in cell or "`" + code[1][1:-1] + "`" in cell
    if code[0] == "list":
        return any(same_literal(code, literal(m)) for m in re.findall(r"\[[^\[\]]*\]", cell) if literal(m))
    return re.search(r"(^|\W)" + re.escape(default) + r"(\W|$)", cell) is not None


def default_problem(cell, defaults):
    """Why a kept default cell disagrees with the code's defaults (not one value, or required), or None."""
    if not cell:
        return f"no default written; the code's is {' | '.join(defaults)}"
    text, is_literal = leading_value(cell)
    if len(defaults) == 1:  # required
        if not (is_literal and literal(text)[0] == "required"):
            return f"the doc's default is {text!r}; the code reads the key without one (required, none, unset or —)"
        return None
    missing = [d for d in defaults if not mentions(cell, d)]
    if not is_literal:
        missing = [d for d in missing if literal(d) is not None and literal(d)[0] == "required"]
    if missing:
        return f"the code's default follows another key ({' | '.join(defaults)}); the doc's cell does not mention " \
               + ", ".join(missing)
    return None


# --- writing ----------------------------------------------------------------------------------------------------

def direct_keys(prefix, code_keys):
    """The keys (not tables) the reading asks directly in the table PREFIX, by name."""
    found = {}
    for name, code in code_keys.items():
        if name.startswith(prefix + ".") and "." not in name[len(prefix) + 1:] and code.kind not in TABLE_KINDS:
            found[name[len(prefix) + 1:]] = code
    return found


def table_lines(header, rows):
    def line(cells):
        return "|" + "|".join(f" {cell} " if cell else " " for cell in cells) + "|"
    return [line(header), "|" + "---|" * len(header)] + [line(row) for row in rows]


def write_block(block, code_keys):
    """(the block's table lines, [(line, problem)])."""
    problems = []
    line = block.start + 1
    header = block.header if block.header[:3] == list(GENERATED) and len(block.header) > 3 \
        else [*GENERATED, *(block.header[3:] or ["meaning"])]
    if block.header and block.header[:3] != list(GENERATED):
        problems.append((line, f"{block.prefix}: the table's first columns are not key, type, default"))
    asked = direct_keys(block.prefix, code_keys)
    kept, order = {}, []
    for number, cells in block.rows:
        cells = (cells + [""] * len(header))[:len(header)]
        for key in row_keys(cells[0]):
            if key not in kept:
                kept[key] = (number, cells)
                order.append(key)
    if not asked and not any(f"{block.prefix}.{key}" in UNCOVERED for key in order):
        problems.append((line, f"{block.prefix}: the samples' reading asks no key in this table (a stale table, or "
                               f"a wrong prefix)"))
    names = [key for key in order if key in asked or f"{block.prefix}.{key}" in UNCOVERED]
    names += sorted(key for key in asked if key not in kept)
    rows = []
    for key in names:
        number, cells = kept.get(key, (line, [""] * len(header)))
        full = f"{block.prefix}.{key}"
        if full in UNCOVERED:
            rows.append([f"`{key}`", *cells[1:]])
            continue
        code = asked[key]
        default = written_default(code)
        if default is None:
            default = cells[2] if key in kept else " | ".join(default_value(d) for d in code.defaults)
            reason = default_problem(default, code.defaults)
            if reason:
                problems.append((number, f"{full}: {reason}"))
        if not cells[3]:
            problems.append((number, f"{full}: no description (write one in the `{header[3]}` column)"))
        rows.append([f"`{key}`", type_cell(code), default, *cells[3:]])
    joined = []
    for row in rows:
        if joined and joined[-1][1:] == row[1:]:
            joined[-1][0] += ", " + row[0]
        else:
            joined.append(list(row))
    return table_lines(header, joined), problems


def generate(doc_text, keys_text, doc_name="docs/SCENES.md"):
    """(the doc as the reading writes it, [problem lines])."""
    code_keys = read_keys(keys_text)
    lines = doc_text.split("\n")
    blocks, found = parse_blocks(lines)
    problems = list(found)
    out, position = [], 0
    for block in blocks:
        table, block_problems = write_block(block, code_keys)
        problems += block_problems
        out += lines[position:block.start + 1] + table + [lines[block.end]]
        position = block.end + 1
    out += lines[position:]
    # What no key table covers: a key whose table has no block, or a table with no block at or below it.
    prefixes = {block.prefix for block in blocks}
    for name, code in sorted(code_keys.items()):
        if code.kind in TABLE_KINDS:
            if not any(p == name or p.startswith(name + ".") or p.startswith(name + "[]") for p in prefixes):
                problems.append((1, f"{name}: the reading asks this {code.kind} but no key table documents it (add "
                                    f"one between `<!-- scene-keys PREFIX -->` and `{END}`)"))
            continue
        prefix = name.rsplit(".", 1)[0] if "." in name else ""
        if prefix not in prefixes:
            problems.append((1, f"{name}: no key table for `{prefix or '(root)'}` (add "
                                f"`<!-- scene-keys {prefix} -->` and `{END}` where it belongs)"))
    problems.sort(key=lambda p: (p[0], p[1]))
    return "\n".join(out), [f"{doc_name}:{line}: {text}" for line, text in problems]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--riffle", required=True, help="the riffle binary (it needs the keys subcommand)")
    parser.add_argument("--doc", default=str(ROOT / "docs" / "SCENES.md"), help="default: docs/SCENES.md")
    parser.add_argument("--write", action="store_true", help="rewrite the doc's key tables in place")
    parser.add_argument("scenes", nargs="+", help="the sample scenes (e.g. tests/data/scene_keys/*.toml)")
    args = parser.parse_args(argv)
    run = subprocess.run([args.riffle, "keys", *args.scenes], capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(run.stderr)
        print(f"{args.riffle} keys failed (exit {run.returncode}): every sample must be a valid scene")
        return 1
    doc = pathlib.Path(args.doc)
    try:
        doc_name = str(doc.resolve().relative_to(pathlib.Path.cwd().resolve()))
    except ValueError:
        doc_name = str(doc)
    text = doc.read_text(encoding="utf-8")
    written, problems = generate(text, run.stdout, doc_name)
    if args.write:
        if written != text:
            doc.write_text(written, encoding="utf-8")
            print(f"{doc_name}: key tables rewritten")
    elif written != text:
        diff = list(difflib.unified_diff(text.splitlines(), written.splitlines(), doc_name,
                                         doc_name + " (as the reading writes it)", n=0, lineterm=""))
        print("\n".join(diff[:60] + ([f"... {len(diff) - 60} more diff lines"] if len(diff) > 60 else [])))
        command = ["tools/riffle-tools", "scene-keys", "--riffle", args.riffle,
                   "--doc", args.doc, "--write", *args.scenes]
        print(f"{doc_name}'s key tables are not what the scene reading gives; rewrite them with:\n  "
              + " ".join(shlex.quote(part) for part in command))
    for problem in problems:
        print(problem)
    print(f"{len(read_keys(run.stdout))} keys read, {len(problems)} left for a person"
          + ("" if args.write or written == text else ", the tables differ"))
    return 1 if problems or (not args.write and written != text) else 0


if __name__ == "__main__":
    sys.exit(main())
