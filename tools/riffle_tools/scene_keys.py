"""docs/SCENES.md checked against the scene reading: runs `RIFFLE keys SCENE...` (every key the reading of the
sample scenes asks for, with its default as the code applies it) and compares it with the key tables of the doc.

  tools/riffle-tools scene-keys --riffle build/riffle [--doc docs/SCENES.md] tests/data/scene_keys/*.toml

A problem, one line each, naming the doc's line (exit 1 if any; then "N keys checked, M problems"):
- a key the reading asks is not documented (the line is that of the table where it belongs, or 1);
- a documented key is never asked by the samples: the doc is stale, or a sample is missing;
- a documented default disagrees with the code's.

The doc. A key table is a Markdown table whose header's first cell is `key`; its `default` column is found by name
(a table without one documents its keys but not their defaults). Each key cell names one or more keys in backticks
(`min`, `max`). The table prefix is named by the paragraph just above the table when that paragraph begins with
backticked tables (`[[solids.spheres]]`, one table per grain:), else by the section heading above it; a heading or
paragraph naming two tables covers both, and parenthesised text in a heading is a comment, not a table. TOML names
become the reading's: an array of tables gets `[]` (`[[fluid.boxes]]` -> `fluid.boxes[].low`), a named table is
`NAME` (`[materials.NAME]`). A key documented twice (one row of a heading covering two tables) agrees if one of
its rows does. Tables (`kind` table or tables in `riffle keys`) count as documented when some key table's prefix
lies in them.

The default cell, normalised simply:
- a probe-kind prefix is dropped (`"surge_front"`: inf -> inf); U+2212 minus is `-`, ∞ is `inf`;
- its leading value is a backticked literal at its start, else its first word (up to a space , ; : or an opening
  parenthesis): a number (numbers compare to 6 significant digits, the code's spelling; `1/7` is a fraction), a
  boolean, a quoted string or a list (`[0, 0, -9.81]`, elements compared as numbers where both are) compare
  exactly; `required` matches required; `none`, `unset` and `—` (no default: the key is read only where a scene
  gives it, which the reading records as required) match required too. Anything else (`l0`, `kind`,
  `probe_<name>.csv`, `the tank's inner floor`) is a description of a default computed from other keys;
- one code default: the leading value must be a literal equal to it;
- several code defaults (the default follows another key: they differ between samples): the cell must mention
  each of them (a number anywhere in the cell, a string or word as written); a cell that leads with a description
  need mention only `required` among them, since its numbers and strings are computed from the samples' own keys.
"""
import argparse
import dataclasses
import math
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

# Keys the samples cannot ask, left out of the coverage check ("a documented key is never asked") only.
UNCOVERED = {
    "solids.initial_state",  # needs a settled bed's checkpoint, which a sample scene cannot carry
}

TABLE_KINDS = ("table", "tables", "named tables")


@dataclasses.dataclass
class CodeKey:
    key: str
    kind: str
    defaults: list


@dataclasses.dataclass
class DocKey:
    key: str
    line: int
    default: object  # the default cell's text, or None when the table has no default column
    siblings: tuple = ()  # the same row's key in the other tables its heading names


@dataclasses.dataclass
class DocTable:
    prefixes: list
    line: int


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
        keys[fields[0]] = CodeKey(fields[0], fields[1], fields[4].split(" | "))
    return keys


TABLE_NAME = re.compile(r"`(\[\[?)([A-Za-z0-9_.]+)\]\]?`")


def strip_parentheses(text):
    while True:
        stripped = re.sub(r"\([^()]*\)", "", text)
        if stripped == text:
            return text
        text = stripped


def table_names(text):
    """[(toml path, is array of tables)] of the backticked `[a.b]` / `[[a.b]]` in text."""
    return [(m.group(2), m.group(1) == "[[") for m in TABLE_NAME.finditer(text)]


def leading_table_names(paragraph):
    """The tables a paragraph begins with (`[[a]]`, `[[b]]` and `[[c]]`, ...), or []."""
    found = re.match(r"\s*((`\[\[?[A-Za-z0-9_.]+\]\]?`)(\s*(,|and|,\s*and)\s*)?)+", paragraph)
    return table_names(found.group(0)) if found else []


def split_row(line):
    cells = re.split(r"(?<!\\)\|", line.strip())
    return [cell.strip() for cell in cells[1:-1]]


def parse_doc(text):
    """The key tables of a SCENES.md: ([DocKey], [DocTable]); prefixes still TOML paths with array flags."""
    lines = text.splitlines()
    heading_names = []
    keys, tables = [], []
    arrays = set()
    for line in lines:
        for name, is_array in table_names(line):
            if is_array:
                arrays.add(name)
    i = 0
    in_code = False
    while i < len(lines):
        line = lines[i]
        if line.startswith("```"):
            in_code = not in_code
            i += 1
            continue
        if in_code:
            i += 1
            continue
        if line.startswith("#"):
            heading_names = table_names(strip_parentheses(line))
            i += 1
            continue
        if line.startswith("|") and i + 1 < len(lines) and re.match(r"\s*\|[\s:|-]+\|\s*$", lines[i + 1]):
            header = [cell.lower() for cell in split_row(line)]
            start = i
            i += 2
            rows = []
            while i < len(lines) and lines[i].startswith("|"):
                rows.append((i + 1, split_row(lines[i])))
                i += 1
            if not header or header[0] != "key":
                continue
            # The paragraph just above the table.
            j = start - 1
            while j >= 0 and not lines[j].strip():
                j -= 1
            paragraph_end = j
            while j >= 0 and lines[j].strip() and not lines[j].startswith(("#", "|", "```")):
                j -= 1
            paragraph = " ".join(lines[j + 1:paragraph_end + 1])
            names = leading_table_names(paragraph) or heading_names
            prefixes = [name for name, _ in names]
            tables.append(DocTable(prefixes, start + 1))
            default_column = header.index("default") if "default" in header else None
            for number, cells in rows:
                if not cells:
                    continue
                default = cells[default_column] if default_column is not None and default_column < len(cells) \
                    else None
                for key in re.findall(r"`([A-Za-z0-9_]+)`", cells[0]):
                    row_keys = [(prefix, key) for prefix in prefixes]
                    for row_key in row_keys:
                        keys.append(DocKey(row_key, number, default, tuple(row_keys)))
            continue
        i += 1
    return keys, tables, arrays


def reading_name(path, arrays, code_keys):
    """A TOML table path (solids.layered_beds.classes) as the reading names it (solids.layered_beds[].classes[])."""
    out = ""
    for part in path.split("."):
        out = part if not out else out + "." + part
        code = code_keys.get(out)
        toml = re.sub(r"\[\]", "", out)
        if (code is not None and code.kind == "tables") or toml in arrays:
            out += "[]"
    return out


# --- defaults ---------------------------------------------------------------------------------------------------

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
    if text == "required":
        return ("required", None)
    if text in NONE_WORDS:
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
    if quoted:
        text = quoted.group(1)
    else:
        text = re.match(r"^[^\s,;:(]*", cell).group(0)
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
    """Why a doc default cell disagrees with the code's defaults, or None."""
    text, is_literal = leading_value(cell)
    if len(defaults) == 1:
        code = literal(defaults[0])
        if not is_literal:
            return f"the doc's default {text!r} is not a value; the code's is {defaults[0]}"
        if code is None or not same_literal(literal(text), code):
            return f"the doc's default is {text}, the code's {defaults[0]}"
        return None
    missing = [d for d in defaults if not mentions(cell, d)]
    if not is_literal:
        missing = [d for d in missing if literal(d) is not None and literal(d)[0] == "required"]
    if missing:
        return f"the code's default follows another key ({' | '.join(defaults)}); the doc's cell does not mention " \
               + ", ".join(missing)
    return None


# --- the check --------------------------------------------------------------------------------------------------

def table_line(name, prefixes):
    """The line of the key table where an undocumented key belongs: that of its table, else of the nearest table
    above it (contact.pairs[].friction -> [contact]), else 1."""
    parent = name
    while "." in parent:
        parent = parent.rsplit(".", 1)[0]
        for candidate in (parent, parent.removesuffix("[]")):
            line = next((line for p, line in prefixes if p == candidate), None)
            if line is not None:
                return line
    return 1


def check(doc_text, keys_text, doc_name="docs/SCENES.md"):
    """([problem lines], number of keys checked) of a SCENES.md text against a `riffle keys` output."""
    code_keys = read_keys(keys_text)
    raw_keys, raw_tables, arrays = parse_doc(doc_text)
    tables = []
    for table in raw_tables:
        tables.append(DocTable([reading_name(p, arrays, code_keys) for p in table.prefixes], table.line))
    def full_name(prefix_key):
        return reading_name(prefix_key[0], arrays, code_keys) + "." + prefix_key[1]

    documented = {}
    for row in raw_keys:
        full = full_name(row.key)
        documented.setdefault(full, []).append(
            DocKey(full, row.line, row.default, tuple(full_name(k) for k in row.siblings)))
    prefixes = [(p, t.line) for t in tables for p in t.prefixes]

    problems = []
    for name, code in sorted(code_keys.items()):
        if code.kind in TABLE_KINDS:
            if not any(p == name or p.startswith(name + ".") or p.startswith(name + "[]") for p, _ in prefixes):
                line = table_line(name, prefixes)
                problems.append((line, f"{doc_name}:{line}: {name}: the reading asks this {code.kind} but no key "
                                       f"table documents it"))
            continue
        rows = documented.get(name)
        if not rows:
            line = table_line(name, prefixes)
            problems.append((line, f"{doc_name}:{line}: {name}: not documented (the reading asks it: {code.kind}, "
                                   f"default {' | '.join(code.defaults)})"))
            continue
        checked = [row for row in rows if row.default is not None]
        if not checked:
            continue
        reasons = [default_problem(row.default, code.defaults) for row in checked]
        if all(reasons):
            # Of several rows (a heading naming two tables), the one whose value is of the code's kind.
            code_kind = (literal(code.defaults[0]) or ("",))[0]
            pick = min(range(len(checked)),
                       key=lambda k: (literal(leading_value(checked[k].default)[0]) or ("",))[0] != code_kind)
            problems.append((checked[pick].line, f"{doc_name}:{checked[pick].line}: {name}: {reasons[pick]}"))
    # A row is stale when its key is asked in none of the tables its heading names.
    rows = {}
    for name, entries in documented.items():
        for row in entries:
            rows.setdefault((row.line, row.siblings or (name,)), row)
    for (line, names), row in sorted(rows.items()):
        if not any(name in code_keys or name in UNCOVERED for name in names):
            problems.append((line, f"{doc_name}:{line}: {', '.join(names)}: documented but never asked by the "
                                   f"samples' reading (stale doc, or no sample sets it up)"))
    problems.sort(key=lambda p: (p[0], p[1]))
    return [text for _, text in problems], len(set(code_keys) | set(documented))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--riffle", required=True, help="the riffle binary (it needs the keys subcommand)")
    parser.add_argument("--doc", default=str(ROOT / "docs" / "SCENES.md"), help="default: docs/SCENES.md")
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
    problems, count = check(doc.read_text(encoding="utf-8"), run.stdout, doc_name)
    for problem in problems:
        print(problem)
    print(f"{count} keys checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
