"""Checks that docs/sdk-reference.md lists every public name of the SDK's headers, and nothing else.

    sdk_reference.py <source dir>            check; exit 1 with a list of what is missing or stale
    sdk_reference.py <source dir> --names    print the public names found, one a line

What counts as a public name, per header of sdk/include/hsr/ (the *-inl.h files are Highway's
per-target kernels that hsr/shading.hpp includes, not for plugins: only their file names count):
  - a macro #defined and not #undef'd again later in the header, except include guards (*_H, *_H_);
  - at namespace scope, outside namespaces named `detail` and Highway's per-target namespace: every
    class, struct, enum, enumerator (of an unnamed enum too), function, function template, variable,
    constant, type alias (using, typedef) and concept;
  - in a class, struct or scoped enum: every public member (data member, member function, nested type,
    enumerator), except constructors, destructors and operators.
The headers are read with a small tokenizer that follows braces, not a compiler: it understands the
shapes these headers use (clang-format's layout, one declaration a statement) and no more.

What the reference must do:
  - name every header in a heading `## \\`hsr/NAME\\``, and no header that does not exist;
  - show every namespace-scope name in backticks somewhere on the page (`hsr::sdk::Scene`,
    `Scene`, `scene_key()` all show the name Scene or scene_key);
  - show every member of a class X in backticks within the section of a heading that names X in
    backticks (nested types as `Outer::Inner`), down to the next heading of the same or a higher level,
    or in a table row whose first cell starts with `X` (a small type described in one row);
  - list in the first cell of its table rows (`| \\`name(...)\\` | ... |`) only names that exist.
"""
import re
import sys
from pathlib import Path

PAGE = "docs/sdk-reference.md"
HEADERS = "sdk/include/hsr"
HIDDEN_NAMESPACES = {"detail", "HWY_NAMESPACE"}
KEYWORDS = {
    "const", "constexpr", "static", "inline", "virtual", "explicit", "extern", "typename", "class", "struct",
    "enum", "union", "unsigned", "signed", "long", "short", "int", "char", "float", "double", "bool", "void",
    "noexcept", "override", "final", "template", "friend", "using", "typedef", "namespace", "return", "mutable",
    "volatile", "auto", "decltype", "requires", "concept", "operator", "public", "private", "protected",
    "default", "delete", "alignas", "sizeof", "__extension__",
}


def strip(text):
    """The header without comments, string and character literals (kept as ""), line splices."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            out.append("\n" * text.count("\n", i, end))
            i = end + 2
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append('""')
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out).replace("\\\n", " ")


def macros(text):
    """Macros #defined and not #undef'd afterwards, include guards left out."""
    last = {}
    for m in re.finditer(r"^\s*#\s*(define|undef)\s+(\w+)", text, re.M):
        last[m.group(2)] = m.group(1)
    return sorted(name for name, what in last.items()
                  if what == "define" and not re.search(r"_H_?$", name))


TOKEN = re.compile(r"[A-Za-z_]\w*|::|->|\.\.\.|\d[\w.']*|\S")


def tokens(text):
    code = "\n".join("" if line.lstrip().startswith("#") else line for line in text.split("\n"))
    return TOKEN.findall(code)


def is_identifier(token):
    return re.fullmatch(r"[A-Za-z_]\w*", token) is not None and token not in KEYWORDS


def skip_template_heads(head):
    """The statement without its leading `template <...>` clauses."""
    while head[:2] == ["template", "<"]:
        depth, k = 0, 1
        for k in range(1, len(head)):
            depth += {"<": 1, ">": -1}.get(head[k], 0)
            if depth == 0:
                break
        head = head[k + 1:]
    return head


def function_name(head):
    """For a function's head (its first `(` at the top level comes before any `=`): its name, or ""
    for the out-of-class definition of a member (`R Class<T>::name(...)`). None for anything else."""
    depth = 0
    for k, t in enumerate(head):
        if t == "<":
            depth += 1
        elif t == ">":
            depth -= 1
        elif depth == 0 and t in ("=", "[", "{"):
            return None
        elif depth == 0 and t == "(":
            if k == 0 or not is_identifier(head[k - 1]) or head[k + 1:k + 2] == ["*"]:
                return None
            return "" if k > 1 and head[k - 2] == "::" else head[k - 1]
    return None


def without_attributes(head):
    """The statement without its attributes ([[gnu::always_inline]], [[nodiscard]]), which the
    tokenizer gives as `[`, `[`, ..., `]`, `]`."""
    out, k = [], 0
    while k < len(head):
        if head[k:k + 2] == ["[", "["]:
            end = k + 2
            while end + 1 < len(head) and head[end:end + 2] != ["]", "]"]:
                end += 1
            k = end + 2
        else:
            out.append(head[k])
            k += 1
    return out


def declared_names(head):
    """The names a statement (tokens before its `;` or `{`) declares, or [] when it declares none."""
    head = skip_template_heads(without_attributes(head))
    if not head or head[0] in ("friend", "static_assert", "return"):
        return []
    if head[0] == "using":
        return [head[1]] if len(head) > 2 and head[2] == "=" else []
    if "concept" in head:
        return [head[head.index("concept") + 1]]
    if "operator" in head:
        return []
    if re.fullmatch(r"[A-Z][A-Z0-9_]+", head[0]) and len(head) > 1 and head[1] == "(":
        return []  # a macro at work (HWY_EXPORT(...), HSR_ABI_CHECK(...))
    if head[0] == "typedef" and "(" in head and head[head.index("(") + 1] == "*":
        return [head[head.index("(") + 2]]  # typedef R (*name)(...)
    function = function_name(head)
    if function is not None:
        return [function] if function else []
    # Split on commas outside brackets: `int32_t x0 = 0, y0 = 0;` declares x0 and y0.
    parts, depth, part = [], 0, []
    for t in head:
        if t in "([<{":
            depth += 1
        elif t in ")]>}":
            depth -= 1
        if t == "," and depth == 0:
            parts.append(part)
            part = []
        else:
            part.append(t)
    parts.append(part)
    names = []
    for part in parts:
        if "(" in part and part.index("(") + 2 < len(part) and part[part.index("(") + 1] == "*":
            names.append(part[part.index("(") + 2])  # a function-pointer field: R (*name)(...)
            continue
        cut = len(part)
        for k, t in enumerate(part):
            if t in ("(", "=", "[", ":", "{"):
                cut = k
                break
        ids = [t for t in part[:cut] if is_identifier(t)]
        if ids and not (cut < len(part) and part[cut] == ":" and cut + 1 < len(part) and part[cut + 1] == ":"):
            names.append(ids[-1])
    return names


class Parser:
    """Walks a header's tokens statement by statement, following namespaces, classes and enums."""

    def __init__(self, toks):
        self.toks = toks
        self.pos = 0
        self.names = set()  # "name" at namespace scope, "Owner::member" for members

    def skip_block(self):
        depth = 0
        while self.pos < len(self.toks):
            t = self.toks[self.pos]
            self.pos += 1
            if t == "{":
                depth += 1
            elif t == "}":
                depth -= 1
                if depth == 0:
                    return

    def add(self, owner, name, hidden):
        if hidden or name in KEYWORDS:
            return
        self.names.add(f"{owner}::{name}" if owner else name)

    def enum_body(self, owner, hidden):
        """Enumerators from the `{` on; `owner` is the enum for a scoped enum, else the enclosing scope."""
        self.pos += 1
        expect_name = True
        depth = 0
        while self.pos < len(self.toks):
            t = self.toks[self.pos]
            self.pos += 1
            if t in "([{":
                depth += 1
            elif t in ")]" or (t == "}" and depth > 0):
                depth -= 1
            elif t == "}":
                return
            elif t == "," and depth == 0:
                expect_name = True
            elif expect_name and is_identifier(t):
                self.add(owner, t, hidden)
                expect_name = False

    def scope(self, owner, default_public, hidden):
        """Statements until the `}` that closes this scope (or the end)."""
        public = default_public
        head = []
        while self.pos < len(self.toks):
            t = self.toks[self.pos]
            if t == "}":
                self.pos += 1
                return
            if t in ("public", "private", "protected") and self.pos + 1 < len(self.toks) \
                    and self.toks[self.pos + 1] == ":" and not head:
                public = t == "public"
                self.pos += 2
                continue
            if t == ";":
                self.pos += 1
                if public:
                    for name in declared_names(head):
                        if name != owner.split("::")[-1]:
                            self.add(owner, name, hidden)
                head = []
                continue
            if t != "{":
                head.append(t)
                self.pos += 1
                continue
            # A `{`: what does it open?
            core = skip_template_heads(head)
            if "namespace" in core:
                name = "::".join(x for x in core[core.index("namespace") + 1:] if x != "::")
                self.pos += 1
                self.scope(owner, True, hidden or bool(set(name.split("::")) & HIDDEN_NAMESPACES))
                head = []
            elif core[:1] == ["extern"] and "(" not in core:
                self.pos += 1
                self.scope(owner, True, hidden)
                head = []
            elif core[:1] == ["enum"] or core[:2] == ["typedef", "enum"]:
                ids = [x for x in core[:core.index(":")] if is_identifier(x)] if ":" in core else \
                    [x for x in core if is_identifier(x)]
                scoped = "class" in core or "struct" in core
                name = ids[-1] if ids else None
                if name and public:
                    self.add(owner, name, hidden)
                inner = (f"{owner}::{name}" if owner else name) if scoped else owner
                self.enum_body(inner, hidden or not public)
                head = ["typedef"] if core[0] == "typedef" else []  # `} name;` follows a typedef
            elif core[:1] in (["struct"], ["class"], ["union"]) or core[:2] in (["typedef", "struct"],):
                k = 2 if core[0] == "typedef" else 1
                name = core[k] if k < len(core) and is_identifier(core[k]) else None
                if name and public:
                    self.add(owner, name, hidden)
                self.pos += 1
                inner = f"{owner}::{name}" if owner and name else (name or owner)
                self.scope(inner, core[k - 1] != "class", hidden or not public)
                head = ["typedef"] if core[0] == "typedef" else []
            else:
                # A function body, a braced initializer, a requires-expression: the head declares.
                if public:
                    for name in declared_names(head):
                        if name != owner.split("::")[-1]:
                            self.add(owner, name, hidden)
                self.skip_block()
                # A body ends the statement; a braced initializer (`= {...}`, `x{1.0f}`) goes on to its `;`.
                head = [] if function_name(without_attributes(head)) is not None else ["="]
        return


def public_names(source):
    names = {}
    for path in sorted((source / HEADERS).iterdir()):
        header = f"hsr/{path.name}"
        if path.name.endswith("-inl.h"):
            names[header] = set()
            continue
        text = strip(path.read_text())
        parser = Parser(tokens(text))
        parser.scope("", True, False)
        found = parser.names | set(macros(text))
        # `typedef struct X {...} X;` declares X twice, as a type and an alias: one name.
        names[header] = {n for n in found if not (n.count("::") == 1 and n.split("::")[0] == n.split("::")[1])}
    return names


def backticked(text):
    return re.findall(r"`([^`\n]+)`", text)


def identifiers(span):
    return set(re.findall(r"[A-Za-z_]\w*", span))


def prose_lines(lines):
    """(index, line) of every line outside fenced code blocks."""
    in_code = False
    for k, line in enumerate(lines):
        if line.lstrip().startswith("```"):
            in_code = not in_code
        elif not in_code:
            yield k, line


def check(source):
    page_path = source / PAGE
    page = page_path.read_text()
    names = public_names(source)
    problems = []
    # The reader is no compiler: should a new shape of declaration throw it off, names would go
    # missing silently. These must always be found.
    every_name = set().union(*names.values())
    for anchor in ("hsr_camera::view_projection", "hsr_light::intensity", "HSR_ELEMENT", "Scene::placement",
                   "Params::real", "Steps::Event::type", "TriangleSetup::depth", "GeometryStage::process",
                   "ZPyramid::is_hidden", "parallel_for_each", "ShadedLightingModel::shade", "PhongSpecular::kind"):
        if anchor not in every_name:
            problems.append(f"the header reader did not find {anchor}: tests/sdk_reference.py needs fixing")

    lines = page.split("\n")
    headings = []  # (line index, level, backticked spans)
    for k, line in prose_lines(lines):
        m = re.match(r"(#+)\s", line)
        if m:
            headings.append((k, len(m.group(1)), backticked(line)))

    def section(index):
        k, level, _ = headings[index]
        end = len(lines)
        for k2, level2, _ in headings[index + 1:]:
            if level2 <= level:
                end = k2
                break
        return "\n".join(lines[k:end])

    all_spans = set()
    for span in backticked(page):
        all_spans |= identifiers(span)

    documented_headers = set()
    for _, level, spans in headings:
        for span in spans:
            if level == 2 and re.fullmatch(r"hsr/[\w.-]+", span):
                documented_headers.add(span)
    for header in sorted(set(names) - documented_headers):
        problems.append(f"{header}: no `## \\`{header}\\`` heading")
    for header in sorted(documented_headers - set(names)):
        problems.append(f"{header}: a heading for a header that does not exist")

    sections_of = {}  # owner path -> identifiers backticked in sections whose heading names it

    def owner_sections(owner):
        if owner not in sections_of:
            pattern = re.compile(r"(?<![\w])(?:\w+::)*" + re.escape(owner) + r"(?!\w)")
            ids = None
            for index, (_, _, spans) in enumerate(headings):
                if any(pattern.search(span) for span in spans):
                    ids = (ids or set())
                    for span in backticked(section(index)):
                        ids |= identifiers(span)
            for row in rows_of.get(owner.split("::")[-1], []):
                ids = (ids or set()) | row
            sections_of[owner] = ids
        return sections_of[owner]

    rows_of = {}  # name -> identifiers backticked in table rows whose first cell is that name
    for line in lines:
        m = re.match(r"\|\s*`([A-Za-z_][\w:]*)", line)
        if m:
            ids = set()
            for span in backticked(line):
                ids |= identifiers(span)
            rows_of.setdefault(m.group(1).split("::")[-1], []).append(ids)

    every = set()
    for header, found in sorted(names.items()):
        for name in sorted(found):
            every |= set(name.split("::"))
            if "::" not in name:
                if name not in all_spans:
                    problems.append(f"{header}: {name} is not listed")
                continue
            owner, member = name.rsplit("::", 1)
            ids = owner_sections(owner)
            if ids is None:
                problems.append(f"{header}: {name}: no heading names `{owner}`")
            elif member not in ids:
                problems.append(f"{header}: {name} is not listed under a heading that names `{owner}`")

    # Stale names: the first cell of a table row names something that exists.
    for k, line in prose_lines(lines):
        m = re.match(r"\|\s*`([^`]+)`", line)
        if not m:
            continue
        lead = re.match(r"[A-Za-z_][\w:.]*", m.group(1).strip())
        if lead is None:
            continue
        name = re.split(r"::|\.", lead.group(0))[-1]
        if name not in every and name != "operator":
            problems.append(f"{PAGE}:{k + 1}: `{lead.group(0)}` is listed but no SDK header declares it")
    return problems


def main():
    source = Path(sys.argv[1])
    if len(sys.argv) > 2 and sys.argv[2] == "--names":
        for header, found in sorted(public_names(source).items()):
            for name in sorted(found):
                print(f"{header}\t{name}")
        return 0
    problems = check(source)
    for p in problems:
        print(p)
    if problems:
        print(f"sdk_reference: {len(problems)} problems: {PAGE} and the headers under {HEADERS} disagree "
              "(the rules are at the top of tests/sdk_reference.py)")
        return 1
    print(f"sdk_reference: {PAGE} lists every public name of {HEADERS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
