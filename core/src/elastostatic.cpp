// Filled in by issue 8.
