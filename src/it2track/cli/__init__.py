"""Command line: ``it2track simulate | reproduce | sweep | optimize | fis | surface``."""
