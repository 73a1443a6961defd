"""Answers in words: each operation of a read form answered over the evaluated sets
(`operations`), the parts an answer carries (`parts`), how things are said (`wording`) and an
answer's picture (`picture`)."""
