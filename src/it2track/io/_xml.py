"""A hostile-input-safe XML reader for FML: a small element tree with line numbers.

Built on the standard library's expat parser with defusedxml's precautions: any document type
declaration (and with it every entity declaration, internal or external) is refused before a
byte of it is expanded, no external resource is ever fetched, and the tree's depth and size are
bounded. Errors are :class:`~it2track.io.FisFormatError` with the file and line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from xml.parsers import expat

from .errors import FisFormatError

__all__ = ["MAX_DEPTH", "MAX_ELEMENTS", "Node", "parse"]

MAX_DEPTH = 64
MAX_ELEMENTS = 1_000_000


@dataclass
class Node:
    """An element: its local tag, namespace, attributes, text, children and line."""

    tag: str
    namespace: str
    attrs: dict[str, str]
    line: int
    children: list[Node] = field(default_factory=list)
    text: str = ""

    def all(self, tag: str) -> list[Node]:
        """The children with this local tag."""
        return [c for c in self.children if c.tag == tag]

    def one(self, tag: str, path: str) -> Node | None:
        """The only child with this tag (``None`` if there is none); two are an error."""
        found = self.all(tag)
        if len(found) > 1:
            raise FisFormatError(path, found[1].line, f"a second <{tag}> in <{self.tag}>")
        return found[0] if found else None


class _Refused(Exception):
    def __init__(self, line: int, message: str) -> None:
        super().__init__(message)
        self.line = line


def parse(text: str, path: str) -> Node:
    """The root element of ``text``.

    Raises
    ------
    FisFormatError
        For malformed XML, a DTD or entity declaration, more than :data:`MAX_DEPTH` levels or
        :data:`MAX_ELEMENTS` elements.
    """
    parser = expat.ParserCreate(namespace_separator=" ")
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    stack: list[Node] = []
    root: list[Node] = []
    count = [0]

    def refuse_dtd(*_: object) -> None:
        raise _Refused(parser.CurrentLineNumber, "a document type declaration (DTD) is refused: "
                       "FML needs none, and entities expanded from one can be hostile")

    def refuse_entity(*_: object) -> None:
        raise _Refused(parser.CurrentLineNumber, "entity declarations are refused")

    def start(name: str, attrs: dict[str, str]) -> None:
        count[0] += 1
        if count[0] > MAX_ELEMENTS:
            raise _Refused(parser.CurrentLineNumber, f"more than {MAX_ELEMENTS} elements")
        if len(stack) >= MAX_DEPTH:
            raise _Refused(parser.CurrentLineNumber, f"elements nested deeper than {MAX_DEPTH}")
        namespace, _, local = name.rpartition(" ")
        node = Node(local, namespace, {k.rpartition(" ")[2]: v for k, v in attrs.items()},
                    parser.CurrentLineNumber)
        if stack:
            stack[-1].children.append(node)
        else:
            root.append(node)
        stack.append(node)

    def end(_: str) -> None:
        stack.pop()

    def chars(data: str) -> None:
        if stack:
            stack[-1].text += data

    parser.StartDoctypeDeclHandler = refuse_dtd
    parser.EntityDeclHandler = refuse_entity
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    try:
        parser.Parse(text, True)
    except _Refused as exc:
        raise FisFormatError(path, exc.line, str(exc)) from None
    except expat.ExpatError as exc:
        raise FisFormatError(path, exc.lineno, f"malformed XML: {expat.errors.messages[exc.code]}"
                             ) from None
    if not root:
        raise FisFormatError(path, None, "no XML element")
    return root[0]
