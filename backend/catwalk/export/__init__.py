"""catwalk.export"""
