"""catwalk.body"""
