// The report writer (issue 9).
