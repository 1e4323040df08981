"""Syntax: the lark grammars (one per dialect), the parser, and the Block/Word/Span types."""
