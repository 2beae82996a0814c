//! Owned scene data built from user input: nodes, links, splines; primitive selection.
