"""What a run recorded and what it reports: samples, verdict, report, trace, cycle times."""
