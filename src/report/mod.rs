//! Accuracy, speed and stability reports (SVG charts + markdown).
