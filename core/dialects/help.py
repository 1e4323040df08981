"""The code help of every dialect as Markdown (docs/codes.md): the same table the editor's hover and completion
show (GET /api/v1/dialects/{name}), so the docs never drift from it.

    python -m core.dialects.help > docs/codes.md
"""

from __future__ import annotations

from core.dialects.codes import Address, Code, CodeTable


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def _with_unit(name: str, addresses: dict[str, Address]) -> str:
    unit = addresses[name].unit if name in addresses else ""
    return f"{name} ({unit})" if unit else name


def code_order(code: Code) -> tuple[str, int]:
    """G before M, then by number (G1, G2 … G10), as the editor's completion lists them."""
    digits = "".join(ch for ch in code.name[1:] if ch.isdigit())
    return code.name[0], int(digits or 0)


def table_markdown(title: str, table: CodeTable) -> str:
    lines = [
        f"## {title}",
        "",
        "| Code | Bedeutung | Pflicht (je eine) | Optional | Beispiel | Merkregel |",
        "|---|---|---|---|---|---|",
    ]
    for c in sorted(table.codes.values(), key=code_order):
        need = "; ".join(" / ".join(_with_unit(a, table.addresses) for a in g) for g in c.help_mandatory())
        opt = ", ".join(_with_unit(a, table.addresses) for a in c.help_optional())
        planned = "" if c.support.value == "yes" else " (noch nicht unterstützt)"
        example = f"`{c.example}`" if c.example else ""
        lines.append(
            f"| {c.name} | {_cell(c.help_de)}{planned} | {need} | {opt} | {example} | {_cell(c.rule_de)} |"
        )
    lines += ["", "| Adresse | Bedeutung | Einheit | Merkregel |", "|---|---|---|---|"]
    lines += [
        f"| {a.name} | {_cell(a.help_de)} | {a.unit} | {_cell(a.rule_de)} |" for a in table.addresses.values()
    ]
    return "\n".join(lines) + "\n"


def codes_markdown() -> str:
    from core.pipeline import DIALECTS  # here: the pipeline imports the tables of this package

    head = (
        "# G- und M-Codes der Dialekte\n\nGenerated from the code tables in `core/dialects/` "
        "(`python -m core.dialects.help > docs/codes.md`); the editor's hover help and completion show the "
        "same entries (`GET /api/v1/dialects/{name}`). Units are those of the addresses; a code's "
        "mandatory column lists groups of which one address each is needed.\n\n"
    )
    return head + "\n".join(table_markdown(d.title_de, d.table) for d in DIALECTS.values())


if __name__ == "__main__":
    print(codes_markdown(), end="")
