(A roughing loop whose step was left at zero: the condition never changes)
G21 G90 G17
#<depth> = 0
o<rough> sub
  o101 while [#<depth> GT -3]
    #<depth> = [#<depth> - 0]
    G1 Z#<depth> F300
  o101 endwhile
o<rough> endsub
o<rough> call
M2
