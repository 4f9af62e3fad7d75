"""Research studies done with profilegen — not part of the installed package.

Each module is one study of a question the product's models raised; it imports profilegen as a
library (some reach its internals, so a study is pinned to the package version it runs with).
What each study found and the command that reproduces it: research/README.md.
"""
